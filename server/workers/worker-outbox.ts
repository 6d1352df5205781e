/*
 * Inside a room worker: the PlayerConnection of a client whose socket lives on the main thread,
 * and the outbox its sends go to. Every send of a tick is copied into the outbox's buffer (bytes
 * shared by several players, a broadcast, are copied once); at the end of the tick the filled part
 * is copied into an array buffer of exactly its size, which is transferred, not copied, to the
 * main thread with the list of operations saying which client gets which slice; closes,
 * errors and join results travel in the same ordered list, so a client sees them in the order the
 * room produced them. The unread-bytes figure the slow-reader rule reads is the one the main
 * thread last reported for the socket.
 */
import { encodeMessage, type ServerMessage } from '../../shared/index.ts'
import type { PlayerConnection, RoomPlayer } from '../rooms/index.ts'
import type { FromWorker, FromWorkerOp } from './worker-protocol.ts'

/** Bytes of the smallest batch buffer. */
const INITIAL_BYTES = 64 * 1024

/** The buffer for a batch of `used` bytes: a power of two from 64 KiB. */
function bufferSizeFor(used: number): number {
  let size = INITIAL_BYTES
  while (size < used) size *= 2
  return size
}

/** The ordered sends and operations of one worker since the last flush. */
export class Outbox {
  private buf = new Uint8Array(INITIAL_BYTES)
  private used = 0
  private ops: FromWorkerOp[] = []
  /** Bytes already in the buffer this batch, by the array they came from (broadcasts). */
  private placed = new Map<Uint8Array, number>()
  /** Bytes sent since the worker started. */
  bytesOut = 0

  /** Queue `bytes` for connection `conn` (`snap` = the snapshot's tick, or -1). */
  send(conn: number, bytes: Uint8Array, snap: number): void {
    let at = this.placed.get(bytes)
    if (at === undefined) {
      at = this.used
      if (this.used + bytes.length > this.buf.length) this.grow(this.used + bytes.length)
      this.buf.set(bytes, at)
      this.used += bytes.length
      this.placed.set(bytes, at)
    }
    this.bytesOut += bytes.length
    this.ops.push({ k: 'send', conn, at, len: bytes.length, snap })
  }

  /** Queue an operation. */
  push(op: FromWorkerOp): void {
    this.ops.push(op)
  }

  /**
   * The batch to post (its buffer is transferred), or null when nothing is queued and `always` is
   * false. The outbox keeps its own buffer and hands over a copy of exactly the filled bytes: a
   * fresh 64 KiB buffer per tick, as this did before, is about 4 MB a second of array buffers per
   * worker, and V8 answers that much external memory with a full mark-compact every second or
   * two (15-16 in bench:room-tick's 2,100 ticks, against 2-3 with the copy; Nov 24). After a big
   * batch the buffer shrinks back to the size the current batch needs, so a big tick does not
   * stay big.
   */
  take(ticks: number, always: boolean): { message: FromWorker; transfer: ArrayBuffer[] } | null {
    if (this.ops.length === 0 && !always) return null
    let buf = new ArrayBuffer(0)
    if (this.used > 0) buf = this.buf.slice(0, this.used).buffer as ArrayBuffer
    const size = bufferSizeFor(this.used)
    if (this.buf.length > size) this.buf = new Uint8Array(size)
    const message: FromWorker = { t: 'batch', ticks, buf, ops: this.ops }
    this.used = 0
    this.ops = []
    this.placed = new Map()
    return { message, transfer: buf.byteLength > 0 ? [buf] : [] }
  }

  private grow(needed: number): void {
    let size = this.buf.length * 2
    while (size < needed) size *= 2
    const next = new Uint8Array(size)
    next.set(this.buf.subarray(0, this.used))
    this.buf = next
  }
}

/** A client's connection as a room in a worker sees it. */
export class WorkerConnection implements PlayerConnection {
  /** The room player, once joined. */
  player: RoomPlayer | null = null
  /** Unread bytes as the main thread last reported them. */
  unread = 0

  constructor(
    readonly id: number,
    private readonly outbox: Outbox,
  ) {}

  /** Encode and send one message. */
  send(message: ServerMessage): void {
    this.outbox.send(this.id, encodeMessage(message), -1)
  }

  /** Send pre-encoded bytes (copied into the batch at once). */
  sendBytes(bytes: Uint8Array, snapshotTick?: number): void {
    this.outbox.send(this.id, bytes, snapshotTick ?? -1)
  }

  /** Send an error reply (through the client's session on the main thread). */
  sendError(code: string, reason: string, seq?: number): void {
    this.outbox.push({ k: 'error', conn: this.id, code, reason, seq })
  }

  /** Unread bytes as last reported by the main thread. */
  buffered(): number {
    return this.unread
  }

  /** Close the socket (on the main thread). */
  close(code: number, reason: string): void {
    this.outbox.push({ k: 'close', conn: this.id, code, reason })
  }
}
