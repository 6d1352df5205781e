/*
 * One connected socket and, once it has joined, its player: identity, cursor, grab, the snapshot
 * delta state, the per-tick input budget, strikes for invalid messages and backpressure state.
 * Sending goes through send() so bytes are counted and a socket that is already closing is left
 * alone.
 */

import type { WebSocket } from 'ws'
import type { ServerMessage } from '../shared/index.ts'
import { encodeMessage, SnapshotEncoder } from '../shared/index.ts'
import type { ServerMetrics } from './metrics.ts'

/** A player's grab: its own mouse joint on a body. */
export interface Grab {
  joint: number
  body: number
}

/** A socket and its player. */
export class ClientSession {
  /** Player id within the room (0 until joined). */
  id = 0
  name = ''
  color = '#888888'
  token = ''
  room = ''
  joined = false
  /** Cursor (m) and whether it moved since the last snapshot. */
  cursorX = 0
  cursorY = 0
  cursorDirty = false
  grab: Grab | null = null
  /** Body whose contacts follow each snapshot (the lab), or 0. */
  inspect = 0
  readonly encoder = new SnapshotEncoder()
  /** Inputs queued for the current tick. */
  inputsThisTick = 0
  /** Index in the room queue of this player's move for the current tick, or -1. */
  queuedMove = -1
  /** Invalid messages since the last heartbeat. */
  strikes = 0
  /** Room tick of the last strike for exceeding the input budget (one strike per tick at most). */
  budgetStrikeTick = -1
  /** Room tick since which the send buffer has been over budget, or -1. */
  behindSince = -1
  /** Answered the last heartbeat ping. */
  alive = true
  /** Bytes sent to this client. */
  bytesSent = 0
  /** Errors sent since the last heartbeat (error replies are rate limited). */
  errorsSent = 0

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

  /** Send pre-encoded bytes; a socket whose unsent data would pass the hard limit is dropped instead. */
  sendBytes(bytes: Uint8Array): void {
    if (!this.open) return
    if (this.ws.bufferedAmount + bytes.length > this.hardBufferLimit) {
      this.metrics.slowClientsClosed.inc()
      this.ws.terminate()
      return
    }
    this.ws.send(bytes)
    this.bytesSent += bytes.length
    this.metrics.bytesSent.inc(bytes.length)
  }

  /** Encode and send one message. */
  send(message: ServerMessage): void {
    this.sendBytes(encodeMessage(message))
  }

  /** Send an error (at most 10 per heartbeat interval, so garbage cannot amplify into replies). */
  sendError(code: string, reason: string, seq?: number): void {
    if (this.errorsSent++ >= 10) return
    this.send(seq === undefined ? { t: 'error', code, reason } : { t: 'error', code, reason, seq })
  }

  /** Close with a code and a reason (truncated to the 123 bytes a close frame allows). */
  close(code: number, reason: string): void {
    if (this.ws.readyState > 1) return
    this.ws.close(code, Buffer.from(reason).subarray(0, 123).toString())
  }
}
