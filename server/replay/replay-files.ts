/*
 * The replay directory: log file names (room, UTC start time, a counter on collision), the one
 * pattern a name must match to be served or read (so `..`, absolute paths, slashes and NUL can
 * never name a file), summaries for GET /replays (read by streaming each file through the log
 * reader, cached by size and mtime), pruning to --replay-keep files, and opening a log for the
 * recorder (a seam the tests replace with failing disks).
 */
import { createReadStream } from 'node:fs'
import { open as openFile, readdir, readFile, stat, unlink } from 'node:fs/promises'
import { dirname, join } from 'node:path'
import {
  PREAMBLE_BYTES,
  type Preamble,
  REPLAY_MAGIC,
  type ReadStatus,
  ReplayLogReader,
  type ReplayRecord,
} from '../../shared/index.ts'

/** Extension of replay logs. */
export const LOG_EXTENSION = '.cclog'
/** A valid log name: room, start time (UTC, ms), optional counter, extension; nothing else. */
export const LOG_NAME_PATTERN = /^[A-Za-z0-9_-]{1,32}-\d{8}T\d{9}Z(?:-\d{1,4})?\.cclog$/

/**
 * A log name's room and start stamp (with its counter), read from the fixed-format end of the name:
 * a room name may itself contain what looks like a stamp (`lobby-99999999T` is a valid room name).
 */
const LOG_NAME_PARTS = /^(.+)-(\d{8}T\d{9}Z(?:-\d{1,4})?)\.cclog$/

/** The room a log belongs to (its name before the start stamp), or '' for a name that is not a log's. */
export function roomOfLog(name: string): string {
  return LOG_NAME_PARTS.exec(name)?.[1] ?? ''
}

/** A log's start stamp and counter as they appear at the end of its name, or ''. */
function stampOfLog(name: string): string {
  return LOG_NAME_PARTS.exec(name)?.[2] ?? ''
}

/** The file name for a room log started at `startMs` (counter > 0 on a name collision). */
export function logFileName(room: string, startMs: number, counter = 0): string {
  const stamp = new Date(startMs).toISOString().replace(/[-:.]/g, '')
  return `${room}-${stamp}${counter > 0 ? `-${counter}` : ''}${LOG_EXTENSION}`
}

/** Whether a requested name is a log name (and so names a file directly inside the directory). */
export function isLogName(name: string): boolean {
  return LOG_NAME_PATTERN.test(name)
}

/** A log as GET /replays lists it. */
export interface LogSummary {
  name: string
  room: string
  /** Start, UTC ISO 8601. */
  start: string
  /** Recorded time (ticks / tick rate), seconds. */
  duration: number
  ticks: number
  size: number
  /**
   * clean: ends with a close record; recording: still being written; torn/corrupt: cut short;
   * empty: its writer stopped before the header was whole (nothing to play); invalid: not a log.
   */
  status: 'clean' | 'recording' | 'torn' | 'corrupt' | 'empty' | 'invalid'
  /** Why it is torn, corrupt or invalid. */
  problem?: string
  /** The process that wrote it. */
  writer?: { host: string; pid: number }
}

/** Everything learned from reading a log through once, without loading any world. */
export interface LogScan {
  preamble: Preamble | null
  header: Extract<ReplayRecord, { type: 'header' }> | null
  status: ReadStatus
  /** Byte offset just past the last hash or keyframe record (0 when none). */
  checkpointBytes: number
  checkpointTick: number
}

/**
 * A read of a log that can go on where it stopped: a log being recorded only grows, so listing it
 * again reads only what was appended (GET /replays once re-read every open log from its start, a
 * cost that grew with each log's size, up to --replay-max-bytes, for every request).
 */
interface LogRead {
  reader: ReplayLogReader
  scan: LogScan
  /** Bytes of the file read so far. */
  bytes: number
  /** The last bytes read (up to TAIL_CHECK), to tell an appended file from a rewritten one. */
  tail: Uint8Array
}

/** Bytes compared before a read goes on: a log cut back (crash recovery) and regrown differs here. */
const TAIL_CHECK = 32

/** Bytes of log files read for listings and scans (tests check that listings read only what is new). */
export const logBytesRead = { total: 0 }

function newRead(): LogRead {
  const reader = new ReplayLogReader()
  const scan: LogScan = {
    preamble: null,
    header: null,
    status: reader.current,
    checkpointBytes: 0,
    checkpointTick: -1,
  }
  return { reader, scan, bytes: 0, tail: new Uint8Array(0) }
}

/** Read `path` on from `read.bytes` through the reader (to the end, or until the reader stops). */
async function readOn(path: string, read: LogRead, onRecord?: (r: ReplayRecord) => void): Promise<void> {
  const { reader, scan } = read
  for await (const chunk of createReadStream(path, { start: read.bytes, highWaterMark: 1 << 20 })) {
    const bytes = chunk as Buffer
    read.bytes += bytes.length
    logBytesRead.total += bytes.length
    read.tail = Buffer.concat([read.tail, bytes.subarray(-TAIL_CHECK)]).subarray(-TAIL_CHECK)
    reader.push(bytes, (r, end) => {
      if (r.type === 'header') scan.header = r
      onRecord?.(r)
      if (r.type === 'hash' || r.type === 'keyframe' || r.type === 'header') {
        scan.checkpointBytes = end
        scan.checkpointTick = r.tick
      }
    })
    if (reader.current.state !== 'reading') break
  }
  scan.preamble = reader.preamble
  scan.status = reader.finalStatus()
}

/** Whether the file still holds the bytes `read` ended with (it was appended to, not rewritten). */
async function continues(path: string, read: LogRead): Promise<boolean> {
  const n = read.tail.length
  if (n === 0) return read.bytes === 0
  const file = await openFile(path, 'r')
  try {
    const now = Buffer.alloc(n)
    const { bytesRead } = await file.read(now, 0, n, read.bytes - n)
    return bytesRead === n && now.equals(read.tail)
  } finally {
    await file.close()
  }
}

/** Stream a log through the reader; `onRecord` sees every accepted record in order. */
export async function scanLog(path: string, onRecord?: (r: ReplayRecord) => void): Promise<LogScan> {
  const read = newRead()
  await readOn(path, read, onRecord)
  read.scan.status = read.reader.finish()
  return read.scan
}

/**
 * Whether a log the reader calls invalid is only a start cut short: no byte contradicts a log (the
 * bytes are a prefix of the magic, or a good preamble followed by an incomplete header).
 */
function cutBeforeHeader(scan: LogScan, size: number, head: Uint8Array): boolean {
  if (scan.status.state !== 'invalid') return false
  if (scan.preamble) return scan.status.records === 0 && scan.status.reason === 'the log has no header record'
  return size < PREAMBLE_BYTES && head.every((b, i) => i >= REPLAY_MAGIC.length || b === REPLAY_MAGIC[i])
}

function statusOf(s: ReadStatus): LogSummary['status'] {
  if (s.closed) return 'clean'
  if (s.state === 'corrupt' || s.state === 'invalid') return s.state
  return 'torn'
}

/**
 * Summaries by path, with the read to go on from. A listing drops the entries of its directory's
 * logs that are gone (pruned, deleted by hand): before, every log ever listed stayed here, with its
 * reader, for the life of the process.
 */
const cache = new Map<string, { size: number; mtime: number; summary: LogSummary; read: LogRead | null }>()

/** Paths of the logs whose summaries are cached (tests check that deleted logs are forgotten). */
export function cachedLogPaths(): string[] {
  return [...cache.keys()]
}

/** Drop the cached summaries of logs of `dir` that are not among `names` (its logs now). */
function forgetDeleted(dir: string, names: readonly string[]): void {
  const here = join(dir, '.')
  const present = new Set(names.map((name) => join(dir, name)))
  for (const path of cache.keys()) if (dirname(path) === here && !present.has(path)) cache.delete(path)
}

/** Listings of a log under way, by path: a second request waits for the same read. */
const reading = new Map<string, Promise<LogSummary>>()

/**
 * Summarize one log (cached while its size and mtime stay the same). A log that has grown since
 * is read on from where the last read stopped, when the reader could go on and the file still
 * holds the bytes it ended with; otherwise it is read again from the start. One read per log at a
 * time: concurrent requests share it.
 */
export async function summarize(dir: string, name: string, open: ReadonlySet<string>): Promise<LogSummary> {
  const path = join(dir, name)
  let summary = reading.get(path)
  if (!summary) {
    summary = summarizeNow(path, name)
    reading.set(path, summary)
    summary.finally(() => reading.delete(path)).catch(() => {})
  }
  const done = await summary
  return open.has(name) ? { ...done, status: 'recording', problem: undefined } : done
}

async function summarizeNow(path: string, name: string): Promise<LogSummary> {
  const info = await stat(path)
  const hit = cache.get(path)
  if (hit && hit.size === info.size && hit.mtime === info.mtimeMs) return hit.summary
  const previous = hit?.read
  const goOn =
    previous !== null &&
    previous !== undefined &&
    info.size > previous.bytes &&
    (await continues(path, previous).catch(() => false))
  const read = goOn ? previous : newRead()
  await readOn(path, read)
  const scan = read.scan
  const head = info.size < PREAMBLE_BYTES ? new Uint8Array(await readFile(path)) : new Uint8Array(0)
  const empty = cutBeforeHeader(scan, info.size, head)
  const rate = scan.preamble?.tickRate || 60
  const ticks = scan.header ? scan.status.lastTick - scan.status.firstTick : 0
  const summary: LogSummary = {
    name,
    room: scan.header?.room ?? roomOfLog(name),
    start: new Date(scan.header?.start ?? info.mtimeMs).toISOString(),
    duration: ticks / rate,
    ticks,
    size: info.size,
    status: empty ? 'empty' : statusOf(scan.status),
  }
  if (scan.header) summary.writer = { host: scan.header.host, pid: scan.header.pid }
  if (empty)
    summary.problem = `nothing recorded: the writer stopped before the header was whole (${info.size} bytes)`
  else if (scan.status.reason) summary.problem = scan.status.reason
  else if (!scan.status.closed) summary.problem = 'no clean-close record'
  const more = read.reader.current.state === 'reading'
  // A read kept for later goes on from here; the header's saved world is not needed for that.
  if (more && scan.header) scan.header = { ...scan.header, world: new Uint8Array(0) }
  cache.set(path, { size: info.size, mtime: info.mtimeMs, summary, read: more ? read : null })
  return summary
}

/** Log names in the directory, oldest first (an absent directory has none). */
export async function listLogNames(dir: string): Promise<string[]> {
  let names: string[]
  try {
    names = await readdir(dir)
  } catch {
    return []
  }
  const logs = names.filter(isLogName)
  const stamp = stampOfLog
  return logs.sort((a, b) => (stamp(a) < stamp(b) ? -1 : stamp(a) > stamp(b) ? 1 : a < b ? -1 : 1))
}

/** Summaries of every log, newest first. */
export async function listLogs(dir: string, open: ReadonlySet<string>): Promise<LogSummary[]> {
  const out: LogSummary[] = []
  const names = await listLogNames(dir)
  forgetDeleted(dir, names)
  for (const name of names.reverse()) {
    try {
      out.push(await summarize(dir, name, open))
    } catch {
      // Deleted between readdir and stat (pruning): not listed.
    }
  }
  return out
}

/**
 * How long an unclosed log must have been left unwritten before pruning may take it: a writer
 * appends at least once a second, so a log touched more recently may belong to a writer the pruner
 * does not know of yet (a room worker's new log, another process on this directory).
 */
export const PRUNE_QUIET_MS = 60_000

/**
 * Delete the oldest logs beyond `keep` (oldest by the start stamp in the name). Never deleted: a
 * log in `open`; an unclosed log written in the last PRUNE_QUIET_MS; a recoverable log (the one
 * crash recovery would reopen: its room's newest log that is not empty, unclosed, with a header,
 * not given up by its writer); a closed log whose deletion would make an older unclosed log of its
 * room the recoverable one (the room would come back at a stale state). Taken: other cleanly
 * closed logs, and unclosed ones that are quiet and not recoverable (superseded by a newer log of
 * their room, cut before their header, given up). Logs that cannot be deleted do not count down
 * `keep`, so the directory holds `keep` logs whenever enough can go. Returns the names deleted.
 * Call it from one place per directory (LogPruner): two prunes at once would both delete the
 * same excess and over-prune.
 */
export async function pruneLogs(
  dir: string,
  keep: number,
  open: ReadonlySet<string>,
  now = Date.now(),
): Promise<string[]> {
  const names = await listLogNames(dir)
  const deleted: string[] = []
  let excess = names.length - keep
  for (const name of names) {
    if (excess <= 0) break
    if (open.has(name)) continue
    const room = roomOfLog(name)
    const ofRoom = names.filter((n) => roomOfLog(n) === room && !deleted.includes(n))
    if (!(await prunable(dir, name, ofRoom, open, now))) continue
    await unlink(join(dir, name)).catch(() => {})
    deleted.push(name)
    excess--
  }
  return deleted
}

/** Whether pruning may delete log `name`; `ofRoom` are its room's logs still there, oldest first. */
async function prunable(
  dir: string,
  name: string,
  ofRoom: readonly string[],
  open: ReadonlySet<string>,
  now: number,
): Promise<boolean> {
  let summary: LogSummary
  let mtime: number
  try {
    mtime = (await stat(join(dir, name))).mtimeMs
    summary = await summarize(dir, name, open)
  } catch {
    return false
  }
  const picked = (await recoveryPick(dir, ofRoom, open)) === name
  if (summary.status === 'clean') {
    // Not the log that hides an older unclosed one from recovery (that room would come back stale).
    const older = ofRoom.slice(0, ofRoom.indexOf(name))
    const next = picked ? await recoveryPick(dir, older, open) : null
    return next === null || !(await recoverable(dir, next, open))
  }
  if (now - mtime < PRUNE_QUIET_MS) return false
  return !picked || !(await recoverable(dir, name, open))
}

/**
 * The log crash recovery considers for a room, given its logs oldest first: the newest that is not
 * empty (cut before its header was whole), or null. Recordings.unclosedLogs applies the same rule.
 */
export async function recoveryPick(
  dir: string,
  names: readonly string[],
  open: ReadonlySet<string> = new Set(),
): Promise<string | null> {
  for (let i = names.length - 1; i >= 0; i--) {
    const summary = await summarize(dir, names[i], open).catch(() => null)
    if (!summary) return null
    if (summary.status !== 'empty') return names[i]
  }
  return null
}

/** Whether recovery would reopen log `name` when it picks it: unclosed, with a header, not given up. */
async function recoverable(dir: string, name: string, open: ReadonlySet<string>): Promise<boolean> {
  const summary = await summarize(dir, name, open).catch(() => null)
  return summary !== null && summary.status !== 'clean' && hasHeader(summary) && !(await givenUp(dir, name))
}

/** Whether a summarized log holds a whole header (something recovery or a replay can start from). */
export function hasHeader(summary: LogSummary): boolean {
  return summary.status !== 'empty' && summary.status !== 'invalid'
}

/**
 * The one pruner of a replay directory in a server process: requests while a prune runs make one
 * more run after it, never two at once (two prunes over one listing deleted twice the excess: 15
 * rooms with --replay-keep 10 left 5 logs). With room workers it runs on the main thread, which
 * knows every worker's open logs; the workers only report the logs they create.
 */
export class LogPruner {
  private running: Promise<void> | null = null
  private again = false

  constructor(
    private readonly dir: string,
    private readonly keep: number,
    private readonly open: ReadonlySet<string>,
    private readonly onError: (error: Error) => void,
    /** The prune itself (tests count the runs). */
    private readonly prune: typeof pruneLogs = pruneLogs,
  ) {}

  /** Prune soon (after the prune under way, if any). */
  request(): void {
    if (this.running) {
      this.again = true
      return
    }
    this.running = (async () => {
      do {
        this.again = false
        await this.prune(this.dir, this.keep, this.open).catch(this.onError)
      } while (this.again)
      this.running = null
    })()
  }

  /** Resolves once no prune is running or requested. */
  async idle(): Promise<void> {
    while (this.running) await this.running
  }
}

/** The file operations a recorder uses (tests inject failing ones). */
export interface LogFile {
  /**
   * Append `bytes`. Resolves with `{ bytesWritten }` as Node's FileHandle does: on a filling disk a
   * write can take only part of them (a short write), and the recorder writes the rest or gives up.
   * A seam that resolves with anything else has written them all.
   */
  write(bytes: Uint8Array): Promise<unknown>
  sync(): Promise<void>
  close(): Promise<void>
  /** Cut the file back to `size` bytes (a record cut by a failed write). */
  truncate?(size: number): Promise<void>
  /** Whether the file still has a name: false once it, or its directory, was deleted. */
  linked?(): Promise<boolean>
  /** Mark the file given up (read-only): crash recovery does not reopen it. Needs no disk space. */
  giveUp?(): Promise<void>
  /** Delete the file (closed first): a new log given up before anything whole was in it. */
  remove?(): Promise<void>
}

/** Open a log file: 'create' fails if it exists; 'append' continues one (recovery). Writes append. */
export type OpenLog = (path: string, mode: 'create' | 'append') => Promise<LogFile>

/** Node's filesystem. */
export const openLogFile: OpenLog = async (path, mode) => {
  // Append mode for both: after a cut-back (truncate) the next write lands at the new end.
  const handle = await openFile(path, mode === 'create' ? 'ax' : 'a')
  return {
    write: (bytes) => handle.write(bytes),
    sync: () => handle.sync(),
    close: () => handle.close(),
    truncate: (size) => handle.truncate(size),
    linked: async () => (await handle.stat()).nlink > 0,
    giveUp: () => handle.chmod(0o444),
    remove: () => unlink(path),
  }
}

/**
 * Whether a log was given up by its writer (read-only: its recording failed and no close record
 * could be written), so that crash recovery does not reopen a room at the tick where its
 * recording stopped.
 */
export async function givenUp(dir: string, name: string): Promise<boolean> {
  try {
    return ((await stat(join(dir, name))).mode & 0o222) === 0
  } catch {
    return false
  }
}
