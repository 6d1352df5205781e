/*
 * Saved scene files on the server (docs/scene-format.md): the `--scene-dir` directory holds one
 * file per scene, named by the first 16 hex digits of its SHA-256 (`0123456789abcdef.json`), so a
 * name is safe by construction (only names matching SCENE_ID can be read) and saving the same scene
 * twice keeps one file. At most `--max-saved-scenes` files (0 turns saving off); a file is written
 * to a temporary name and renamed, so a reader never sees half a scene. A scene is checked
 * (parseScene, then built once with buildScene) before it is kept, so every kept file opens.
 *
 * Rooms (on worker threads) and the HTTP routes (on the main thread) each make their own store
 * over the same directory; reads and writes are synchronous and small (at most SCENE_LIMITS.bytes).
 * save() throws on a directory that cannot be made or written; callers turn that into a refusal.
 */
import { createHash } from 'node:crypto'
import { existsSync, mkdirSync, readdirSync, readFileSync, renameSync, writeFileSync } from 'node:fs'
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
    if (existsSync(path)) return { ok: true, id, text, scene: parsed.scene }
    mkdirSync(this.dir, { recursive: true })
    const count = readdirSync(this.dir).filter((f) => FILE.test(f)).length
    if (count >= this.maxScenes)
      return {
        ok: false,
        error: `this server keeps at most ${this.maxScenes} saved scenes, and has that many`,
      }
    const temporary = join(this.dir, `.${id}.${process.pid}.tmp`)
    writeFileSync(temporary, text)
    renameSync(temporary, path)
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
    return { ok: true, id, text, scene: parsed.scene }
  }
}
