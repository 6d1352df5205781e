/*
 * What a room needs from a player's connection. The WebSocket session (client-session.ts)
 * implements it; tests drive a room with fake connections; worker threads or lockstep streams can
 * put their own transport behind it. The room never touches a socket directly.
 */
import type { ServerMessage } from '../../shared/index.ts'

/** The close code that drops a connection at once, without a closing handshake (as the peer sees it). */
export const DROP_CONNECTION = 1006

/** A player's connection as the room sees it. */
export interface PlayerConnection {
  /** Encode and send one message. */
  send(message: ServerMessage): void
  /** Send pre-encoded bytes (one encoding shared by many players); `snapshotTick` marks a snapshot. */
  sendBytes(bytes: Uint8Array, snapshotTick?: number): void
  /** Send an error reply (the connection rate-limits these). */
  sendError(code: string, reason: string, seq?: number): void
  /** Bytes sent or queued that the peer is not known to have read (what the slow-reader rule measures). */
  buffered(): number
  /** Close with a code and a reason; DROP_CONNECTION drops it at once without a handshake. */
  close(code: number, reason: string): void
}
