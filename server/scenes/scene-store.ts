/*
 * Saved scene files on the server (docs/scene-format.md): the `--scene-dir` directory holds one
 * file per scene, named by the first 16 hex digits of its SHA-256 (`0123456789abcdef.json`), so a
 * name is safe by construction (only names matching SCENE_ID can be read) and saving the same scene
 * twice keeps one file. A file is written to a temporary name and renamed, so a reader never sees
 * half a scene. A scene is checked (parseScene, then built once with buildScene) before it is
 * kept, so every kept file opens.
 *
 * The store is bounded: at most `--max-saved-scenes` files (0 turns saving off) and
 * `--max-saved-scene-bytes` bytes in all. A save that would pass either first removes the scenes
 * used longest ago (a scene is used when it is saved, saved again, fetched or opened in a room:
 * its file's modification time is set then), oldest first, ties by name, until the new one fits;
 * a scene larger than the byte bound by itself is refused and removes nothing. So a full server
 * keeps saving, and a share link stays good while its scene is among the most recently used.
 * Refusing new saves once full (the rule before) left a public server unable to save for good.
 *
 * Rooms (on worker threads) and the HTTP routes (on the main thread) each make their own store
 * over the same directory; reads and writes are synchronous and small (at most SCENE_LIMITS.bytes).
 * save() throws on a directory that cannot be made or written; callers turn that into a refusal.
 */
import { createHash } from 'node:crypto'
import {
  existsSync,
  mkdirSync,
  readdirSync,
  readFileSync,
  renameSync,
  statSync,
  unlinkSync,
  utimesSync,
  writeFileSync,
} from 'node:fs'
import { join } from 'node:path'
import { buildScene, parseScene, type SceneFile } from '../../games/index.ts'

/** A saved scene's id: 16 lowercase hex digits. */
export const SCENE_ID = /^[0-9a-f]{16}$/

const FILE = /^[0-9a-f]{16}\.json$/

/** The outcome of saving or reading a scene: its id and text, or why not. */
export type StoredScene =
  | { ok: true; id: string; text: string; scene: SceneFile }
  | { ok: false; error: string }

/** The saved scenes in one directory (see the file comment). */
export class SceneStore {
  constructor(
    private readonly dir: string,
    private readonly maxScenes: number,
    /** Bytes of saved scenes kept in all (--max-saved-scene-bytes). */
    private readonly maxBytes: number,
  ) {}

  /**
   * Check a scene file's text and keep it; its id, or the first error naming the field. `build`
   * false skips building it once (a room saving its own world: the file came from a world).
   */
  save(text: string, build = true): StoredScene {
    if (this.maxScenes === 0) return { ok: false, error: 'this server does not keep saved scenes' }
    const parsed = parseScene(text)
    if (!parsed.ok) return parsed
    if (build) {
      const built = buildScene(parsed.scene)
      if (!built.ok) return built
    }
    const id = createHash('sha256').update(text).digest('hex').slice(0, 16)
    const path = join(this.dir, `${id}.json`)
    if (existsSync(path)) {
      touch(path)
      return { ok: true, id, text, scene: parsed.scene }
    }
    const size = Buffer.byteLength(text)
    if (size > this.maxBytes)
      return {
        ok: false,
        error: `this server keeps at most ${this.maxBytes} bytes of saved scenes; this one has ${size}`,
      }
    mkdirSync(this.dir, { recursive: true })
    this.makeRoom(size)
    const temporary = join(this.dir, `.${id}.${process.pid}.tmp`)
    writeFileSync(temporary, text)
    renameSync(temporary, path)
    touch(path)
    return { ok: true, id, text, scene: parsed.scene }
  }

  /** A kept scene by id, checked again (the file may have been edited on disk), or why not. */
  read(id: string): StoredScene {
    if (!SCENE_ID.test(id))
      return { ok: false, error: `"${id.slice(0, 40)}" is not a scene id (16 hex digits)` }
    let text: string
    try {
      text = readFileSync(join(this.dir, `${id}.json`), 'utf8')
    } catch {
      return { ok: false, error: `no saved scene ${id} on this server` }
    }
    const parsed = parseScene(text)
    if (!parsed.ok) return { ok: false, error: `saved scene ${id} no longer opens: ${parsed.error}` }
    touch(join(this.dir, `${id}.json`))
    return { ok: true, id, text, scene: parsed.scene }
  }

  /** Remove the scenes used longest ago until one more of `size` bytes fits both bounds. */
  private makeRoom(size: number): void {
    const kept: Array<{ path: string; name: string; bytes: number; used: number }> = []
    for (const name of readdirSync(this.dir)) {
      if (!FILE.test(name)) continue
      const path = join(this.dir, name)
      try {
        const info = statSync(path)
        kept.push({ path, name, bytes: info.size, used: info.mtimeMs })
      } catch {
        // Removed meanwhile (another thread's store made room too).
      }
    }
    kept.sort((a, b) => a.used - b.used || (a.name < b.name ? -1 : 1))
    let count = kept.length
    let bytes = 0
    for (const k of kept) bytes += k.bytes
    for (const k of kept) {
      if (count + 1 <= this.maxScenes && bytes + size <= this.maxBytes) break
      try {
        unlinkSync(k.path)
      } catch (error) {
        if ((error as NodeJS.ErrnoException).code !== 'ENOENT') throw error
      }
      count--
      bytes -= k.bytes
    }
  }
}

/** The last use stamped by this thread (ms since 1970, fractional): stamps only go forward. */
let lastUse = 0

/**
 * Mark a kept scene as used now (its modification time); a read-only directory just keeps the old
 * time. The stamp comes from this clock, to the microsecond and strictly increasing, not from the
 * file system's (which may count in ticks of a few ms, so a fetch right after a save could look
 * older than it).
 */
function touch(path: string): void {
  let now = performance.timeOrigin + performance.now()
  if (now <= lastUse) now = lastUse + 0.001
  lastUse = now
  try {
    utimesSync(path, now / 1000, now / 1000)
  } catch {
    // Not ours to change (a read-only mount): the scene is still served.
  }
}
