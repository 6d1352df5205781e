/*
 * What the transport does about a client that breaks the rules (issue 11): strikes with their
 * `error` messages (more than --max-rejects within a heartbeat close the socket with 1008), the
 * per-tick input budget (one strike per tick), the per-client message rate (message-budget.ts:
 * every frame and WebSocket pong counts, at most one strike per tick, and a client at three times
 * the rate or more is closed at once and its address reported through onFlood), and dropping a
 * client: the close frame goes out, nothing more it sends is read, and the socket is terminated
 * after a short grace whether or not it answers (a peer ignoring the close frame once made the
 * server decode and log 930,000 frames in 3 s). transport.ts routes the messages; join-flow.ts
 * uses these for joins.
 */

import type { Duplex } from 'node:stream'
import { CLOSE_CODES } from '../../shared/index.ts'
import type { ServerConfig } from '../config/index.ts'
import type { LogLimiter, ServerMetrics } from '../hosting/index.ts'
import { type Access, addressKey, type MessageBudget } from '../http/index.ts'
import type { ClientSession } from './client-session.ts'

/** The transport's view of one connection: its session, socket, access and message budget. */
export interface Peer {
  session: ClientSession
  socket: Duplex
  address: string
  access: Access
  budget: MessageBudget
  /** Set once the server has decided to close it: nothing more it sends is read. */
  dropped: boolean
  /** Its join waits for the room directory's answer (one claim per socket at a time). */
  joining: boolean
}

/** Time a dropped client's socket stays open for its close frame to leave (ms). */
export const DROP_GRACE_MS = 1000

/** Over-budget messages cost at most one strike per this many ms (one tick). */
const RATE_STRIKE_INTERVAL_MS = 1000 / 60

/** Strikes, budgets, the message rate and drops for the clients of one transport. */
export class PeerPolicy {
  /** Told the address of a client closed for flooding messages (the server penalizes it). */
  onFlood: ((address: string) => void) | null = null

  constructor(
    private readonly config: ServerConfig,
    private readonly metrics: ServerMetrics,
    /** Rate-limited warnings about clients (the transport's). */
    private readonly warnings: LogLimiter,
  ) {}

  /**
   * Close a client and stop reading from it: the close frame (reason cut to 123 bytes) goes out,
   * the socket is paused so nothing more is decoded, and it is terminated after DROP_GRACE_MS.
   */
  drop(peer: Peer, code: number, reason: string): void {
    if (peer.dropped) return
    peer.dropped = true
    peer.session.close(code, reason)
    peer.socket.pause()
    const ws = peer.session.ws
    setTimeout(() => ws.terminate(), DROP_GRACE_MS).unref()
  }

  /**
   * A refused message: one strike, and an `error` (with the input's `seq` when it has one), except
   * that the strike which passes --max-rejects closes the socket instead, its reason naming this
   * refusal.
   */
  reject(peer: Peer, code: string, reason: string, seq?: number): void {
    const session = peer.session
    this.metrics.rejected.inc({ reason: code })
    session.strikes++
    if (session.strikes > this.config.maxRejects) {
      this.warnings.warn(
        addressKey(peer.address),
        { player: session.id, address: peer.address, reason },
        'disconnecting a client that keeps sending invalid messages',
      )
      this.drop(peer, CLOSE_CODES.policy, `too many invalid messages; last: ${reason}`)
      return
    }
    session.sendError(code, reason, seq)
  }

  /**
   * Over the per-tick input budget: the input is dropped and answered (`input-budget`, with its
   * `seq`), but it counts as a strike only once per tick, so a burst after a network hiccup costs
   * little while a sustained flood is disconnected.
   */
  private overBudget(peer: Peer, tick: number, reason: string, seq?: number): void {
    const session = peer.session
    if (session.budgetStrikeTick === tick) {
      this.metrics.rejected.inc({ reason: 'input-budget' })
      session.sendError('input-budget', reason, seq)
      return
    }
    session.budgetStrikeTick = tick
    this.reject(peer, 'input-budget', reason, seq)
  }

  /**
   * Draw one frame from the client's message rate; over it, false, counted, and at most one
   * strike (with an `error` message-rate) per tick, or, at three times the rate, a drop.
   */
  withinRate(peer: Peer): boolean {
    if (peer.budget.take()) return true
    if (peer.budget.flooded()) {
      // At three times the rate or more: closed at once, not after --max-rejects strikes (one per
      // tick), and its address may not reconnect for a while (onFlood). With strikes alone, 32
      // sockets of one address flooding pongs each lived for seconds and stalled the server.
      this.metrics.rejected.inc({ reason: 'message-rate' })
      this.warnings.warn(
        addressKey(peer.address),
        { player: peer.session.id, address: peer.address },
        'disconnecting a client flooding messages',
      )
      this.drop(peer, CLOSE_CODES.policy, this.rateReason())
      this.onFlood?.(peer.address)
      return false
    }
    if (peer.budget.strikeDue(RATE_STRIKE_INTERVAL_MS)) this.reject(peer, 'message-rate', this.rateReason())
    else this.metrics.rejected.inc({ reason: 'message-rate' })
    return false
  }

  /** Why an over-rate client gets an error or is closed (built only when one is sent). */
  private rateReason(): string {
    return `message rate exceeded: at most ${this.config.maxMessagesPerSecond} messages per second`
  }

  /** A strike the room reported: over the input budget (once per tick), or a refused message. */
  roomStrike(
    peer: Peer,
    code: 'input-budget' | 'invalid',
    reason: string,
    tick: number,
    seq: number | undefined,
  ): void {
    if (peer.dropped) return
    if (code === 'input-budget') this.overBudget(peer, tick, reason, seq)
    else this.reject(peer, code, reason, seq)
  }
}
