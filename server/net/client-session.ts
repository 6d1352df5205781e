/*
 * One connected socket: the WebSocket implementation of PlayerConnection, plus what the transport
 * tracks per socket (strikes for invalid messages, heartbeat) and, once it has
 * joined, its seat in a room. Sending goes through sendBytes() so bytes are counted and a socket that
 * is already closing is left alone.
 */

import type { WebSocket } from 'ws'
import { encodeMessage, type ServerMessage } from '../../shared/index.ts'
import type { ServerMetrics } from '../hosting/index.ts'
import { DROP_CONNECTION, type PlayerConnection, type RoomSeat } from '../rooms/index.ts'
import { cutUtf8 } from './close-reason.ts'
import { UnreadBytes } from './unread-bytes.ts'

/** A socket and, once joined, its player in a room; the room sees it as a PlayerConnection. */
export class ClientSession implements PlayerConnection {
  /** Its place in a room, once it has asked to join (null before and after leaving). */
  seat: RoomSeat | null = null
  /** Invalid messages since the last heartbeat. */
  strikes = 0
  /** Room tick of the last strike for exceeding the input budget (one strike per tick at most). */
  budgetStrikeTick = -1
  /** Answered the last heartbeat ping. */
  alive = true
  /** Bytes sent to this client. */
  bytesSent = 0
  /** What the client has been sent and not confirmed reading (by acking a later snapshot). */
  readonly unread = new UnreadBytes()

  constructor(
    readonly ws: WebSocket,
    readonly urlRoom: string,
    private readonly metrics: ServerMetrics,
    /** Unsent bytes beyond which the socket is dropped at once (memory bound per client). */
    private readonly hardBufferLimit: number,
  ) {}

  /** True while the socket can take data. */
  get open(): boolean {
    return this.ws.readyState === 1
  }

  /**
   * Send pre-encoded bytes (the snapshot of `snapshotTick`, when given); a socket whose unsent
   * data would pass the hard limit is dropped instead.
   */
  sendBytes(bytes: Uint8Array, snapshotTick?: number): void {
    if (!this.open) return
    if (this.ws.bufferedAmount + bytes.length > this.hardBufferLimit) {
      this.metrics.slowClientsClosed.inc()
      this.ws.terminate()
      return
    }
    this.ws.send(bytes)
    this.bytesSent += bytes.length
    this.metrics.bytesSent.inc(bytes.length)
    if (snapshotTick !== undefined) this.unread.snapshotSent(snapshotTick, this.bytesSent)
  }

  /** Encode and send one message. */
  send(message: ServerMessage): void {
    this.sendBytes(encodeMessage(message))
  }

  /**
   * Send an error. Every refused message gets one (at most one per message received, and the
   * message rate bounds those), so a client can account for each input it sent.
   */
  sendError(code: string, reason: string, seq?: number): void {
    this.send(seq === undefined ? { t: 'error', code, reason } : { t: 'error', code, reason, seq })
  }

  /** Bytes not known to be read by the client: unsent, or sent after the last snapshot it acked. */
  buffered(): number {
    return this.unread.unread(this.bytesSent, this.ws.bufferedAmount)
  }

  /** Player id for logs (0 before joining). */
  get id(): number {
    return this.seat?.playerId ?? 0
  }

  /**
   * Close with a code and a reason (cut on a character boundary to the 123 bytes a close frame
   * allows); DROP_CONNECTION terminates the socket at once.
   */
  close(code: number, reason: string): void {
    if (code === DROP_CONNECTION) {
      this.ws.terminate()
      return
    }
    if (this.ws.readyState > 1) return
    this.ws.close(code, cutUtf8(reason))
  }
}
