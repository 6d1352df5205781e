/*
 * The page's queue of inputs on their way to the room. The server takes at most `inputsPerTick`
 * inputs per player per tick and drops the rest, so commands are sent at most a share of that
 * budget per animation frame (two frames' worth can land in one server tick, and moves and pings
 * need room too): a burst of clicks is spread over a few frames, and the player is told it is
 * queued. A server that stalls still reads several frames' inputs in one tick and drops some,
 * answering each by its seq: the spawns among them (SpawnTracker) are queued again, so no
 * clicked spawn is lost.
 */
import type { SimCommand } from '../../shared/index.ts'
import { SpawnTracker } from './spawn-tracker.ts'

/** Paced, ordered commands for one connection. */
export class InputOutbox {
  /** Spawns sent and not yet seen added. */
  readonly spawns = new SpawnTracker()
  private readonly queue: SimCommand[] = []
  private sentThisFrame = 0
  private queuedNoticeShown = false
  private resent = 0
  private givenUp = 0

  constructor(
    /** Send one command now (the sender reports spawns to `spawns.sent`). */
    private readonly transmit: (cmd: SimCommand) => void,
    /** Show the player a notice. */
    private readonly tell: (text: string) => void,
  ) {}

  /** Commands waiting for room in the budget. */
  get length(): number {
    return this.queue.length
  }

  /** Queue one command after the ones already waiting. */
  push(cmd: SimCommand): void {
    this.queue.push(cmd)
  }

  /** A new animation frame: its share of the budget is free again. */
  startFrame(): void {
    this.sentThisFrame = 0
  }

  /** Send what this frame's share of a budget of `perTick` inputs allows. */
  drain(perTick: number): void {
    const quota = Math.max(1, Math.floor((perTick - 2) / 3))
    while (this.queue.length > 0 && this.sentThisFrame < quota) {
      this.transmit(this.queue.shift()!)
      this.sentThisFrame++
    }
    if (this.queue.length > 0 && !this.queuedNoticeShown) {
      this.queuedNoticeShown = true
      this.tell(`Sending your next ${this.queue.length} actions a few at a time, so the room keeps up.`)
    }
    if (this.queue.length === 0) this.queuedNoticeShown = false
  }

  /** The server dropped input `seq` over the budget: a spawn goes first in the queue again. */
  dropped(seq: number): void {
    const wasSpawn = this.spawns.has(seq)
    const again = this.spawns.dropped(seq)
    if (!again) {
      if (wasSpawn) this.givenUp++
      return
    }
    this.queue.unshift(again)
    this.resent++
  }

  /** How many dropped spawns were queued again since the last call (for one notice per frame). */
  takeResent(): number {
    const n = this.resent
    this.resent = 0
    return n
  }

  /** How many dropped spawns were given up (sent MAX_SENDS times) since the last call. */
  takeGivenUp(): number {
    const n = this.givenUp
    this.givenUp = 0
    return n
  }
}
