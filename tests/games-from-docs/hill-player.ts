/*
 * A player of the hill game written from shared/protocol/PROTOCOL.md alone: a `ws` socket and
 * standard MessagePack (msgpackr without records, int64 read as numbers), nothing of Concord's own
 * client code. It joins in snapshot mode, keeps the newest snapshot tick, the last `view` and its tick,
 * every `game` event with its tick and every `error`, and sends `cmd` messages.
 */
import { Packr, Unpackr } from 'msgpackr'
import WebSocket from 'ws'
import { until } from '../support/wait.ts'
import { PUCK_DAMPING, PUCK_DENSITY, PUCK_RADIUS, PUSH_IMPULSE } from './games/hill/layout.ts'

const packr = new Packr({ useRecords: false })
const unpackr = new Unpackr({ useRecords: false, int64AsType: 'number' })

/** The hill game's view of one player (games/hill/index.ts `view`). */
export interface HillView {
  phase: string
  held: Record<string, number>
  need: number
  king: number
  winner: number
  me: number
  nextPush: number
  away: number
}

export type Message = { t: string } & Record<string, unknown>

export class HillPlayer {
  readonly received: Message[] = []
  readonly events: unknown[] = []
  /** The tick of each of `events` (game events come every tick, views only with snapshots). */
  readonly eventTicks: number[] = []
  readonly errors: Array<{ code: string; reason: string; seq?: number }> = []
  id = 0
  rules: Record<string, unknown> = {}
  tick = 0
  view: HillView | null = null
  /** The tick `view` shows. */
  viewTick = 0
  private seq = 0
  private closed: Promise<void>

  private constructor(private readonly socket: WebSocket) {
    socket.on('message', (data: Buffer) => {
      const m = unpackr.unpack(data) as Message
      this.received.push(m)
      if (m.t === 'welcome') {
        this.id = m.id as number
        this.rules = m.rules as Record<string, unknown>
      } else if (m.t === 'snap') this.tick = Math.max(this.tick, m.tick as number)
      else if (m.t === 'view') {
        this.view = m.view as HillView
        this.viewTick = m.tick as number
      } else if (m.t === 'game') {
        for (const e of m.events as unknown[]) {
          this.events.push(e)
          this.eventTicks.push(m.tick as number)
        }
      } else if (m.t === 'error')
        this.errors.push(m as unknown as { code: string; reason: string; seq?: number })
    })
    this.closed = new Promise((resolve) => socket.once('close', () => resolve()))
  }

  /** Joins `room` of `url` (http://host:port) as a player of the hill game, in snapshot mode. */
  static async join(
    url: string,
    room: string,
    name: string,
    extra: Record<string, unknown> = {},
  ): Promise<HillPlayer> {
    const socket = new WebSocket(`${url.replace(/^http/, 'ws')}/ws?room=${room}`)
    await new Promise<void>((resolve, reject) => {
      socket.once('open', () => resolve())
      socket.once('error', reject)
    })
    const player = new HillPlayer(socket)
    player.send({ t: 'join', v: 3, room, name, mode: 'snapshot', game: 'hill', ...extra })
    await until(() => player.id !== 0 || player.errors.length > 0, `${name}'s welcome`)
    if (player.id === 0) throw new Error(`join refused: ${JSON.stringify(player.errors)}`)
    return player
  }

  send(message: Record<string, unknown>): void {
    this.socket.send(packr.pack(message))
  }

  /** Sends a game command; returns its seq. */
  command(k: string, a: unknown): number {
    this.seq += 1
    this.send({ t: 'cmd', seq: this.seq, k, a })
    return this.seq
  }

  /** The error answering `seq`, if one came. */
  errorFor(seq: number): { code: string; reason: string } | undefined {
    return this.errors.find((e) => e.seq === seq)
  }

  /** Waits until `seq` is refused (resolves with the error) or fails. */
  async refusal(seq: number, what: string): Promise<{ code: string; reason: string }> {
    await until(() => this.errorFor(seq) !== undefined, what)
    return this.errorFor(seq)!
  }

  /**
   * Pushes once the cooldown allows and waits until the room applied it: the view's `nextPush`
   * moves on (a refusal throws with its reason).
   */
  async push(x: number, y: number): Promise<void> {
    await until(() => this.view !== null && this.tick >= this.view.nextPush, `${this.id}'s push cooldown`)
    const before = this.view!.nextPush
    const seq = this.command('push', { x, y })
    await until(
      () => this.errorFor(seq) !== undefined || this.view!.nextPush !== before,
      `push ${seq} applied`,
    )
    const error = this.errorFor(seq)
    if (error) throw new Error(`push refused: ${error.code}: ${error.reason}`)
  }

  async close(): Promise<void> {
    this.socket.close()
    await this.closed
  }
}

/** A puck's mass (kg): a disc of radius PUCK_RADIUS and density PUCK_DENSITY. */
export const MASS = Math.PI * PUCK_RADIUS * PUCK_RADIUS * PUCK_DENSITY
/** The pushes (each at most 1 long) whose impulses sum to what moves a puck `d` metres. */
export function pushesFor(d: number): number[] {
  let left = (MASS * PUCK_DAMPING * d) / PUSH_IMPULSE
  const out: number[] = []
  while (left > 1e-12) {
    out.push(Math.min(1, left))
    left -= 1
  }
  return out
}
