/*
 * Spawns the player clicked, followed until the server confirms them, so that none is lost. The
 * page paces its inputs within the room's per-tick budget, but a server that stalls (a loaded
 * machine) reads the inputs of several frames in one tick and may refuse the excess. So each
 * spawn sent is kept until an `events` message adds its body: one naming this player and one of
 * the spawn's seqs (PROTOCOL.md: a spawned body carries its spawner's `player` and `seq`), or,
 * from a server that does not name spawners, a dynamic body with its shape where it was dropped;
 * or until the server refuses it by its seq (a full room: not worth sending again). One still
 * unconfirmed once the room has run RESEND_TICKS plus a round trip of ticks past the tick it was
 * sent at was dropped: it is sent again, at most MAX_SENDS times.
 */
import { clampToWorld, type SpawnCommand, type WireBody, type WireShape } from '../shared/index.ts'

/** Room ticks after which an unconfirmed spawn counts as dropped (besides the round trip). */
export const RESEND_TICKS = 30
/** How often one spawn is sent at most. */
export const MAX_SENDS = 3

interface PendingSpawn {
  /** Every seq this spawn went out with (the latest last): any of them may come back. */
  seqs: number[]
  cmd: SpawnCommand
  /** The room's tick as this page knew it when the spawn was sent. */
  sentTick: number
  sends: number
}

const sameShape = (a: WireShape, b: WireShape): boolean => {
  if (a.type !== b.type) return false
  if (a.type === 'circle' && b.type === 'circle') return a.radius === b.radius
  if (a.type === 'box' && b.type === 'box') return a.hw === b.hw && a.hh === b.hh
  if (a.type === 'polygon' && b.type === 'polygon')
    return a.v.length === b.v.length && a.v.every((v, i) => v === b.v[i])
  return false
}

/** The spawns sent and not yet seen in the world. */
export class SpawnTracker {
  private readonly pending: PendingSpawn[] = []

  /** How many spawns are waiting for confirmation. */
  get size(): number {
    return this.pending.length
  }

  /** A spawn went out with `seq` while the room was at `tick`. */
  sent(seq: number, cmd: SpawnCommand, tick: number): void {
    const known = this.pending.find((p) => p.cmd === cmd)
    if (known) {
      known.seqs.push(seq)
      known.sentTick = tick
      known.sends++
    } else this.pending.push({ seqs: [seq], cmd, sentTick: tick, sends: 1 })
  }

  /**
   * A body was added: the pending spawn it names (player `ownId`, one of its seqs) is confirmed;
   * a body naming another player confirms nothing; one naming none confirms the oldest pending
   * spawn it matches by shape and point.
   */
  added(body: WireBody, ownId = 0): void {
    if (body.kind !== 2) return
    if (typeof body.player === 'number' && typeof body.seq === 'number' && ownId !== 0) {
      const seq = body.seq
      const mine = body.player === ownId ? this.pending.findIndex((p) => p.seqs.includes(seq)) : -1
      if (mine >= 0) this.pending.splice(mine, 1)
      return
    }
    const i = this.pending.findIndex((p) => {
      const at = clampToWorld(p.cmd.x, p.cmd.y)
      // Created at the spawn point; a little slack in case the pose is read after the first step.
      const slack = 0.002 + (Math.abs(p.cmd.vx ?? 0) + Math.abs(p.cmd.vy ?? 0) + 1) / 30
      return (
        sameShape(p.cmd.shape, body.shape) &&
        Math.abs(body.x / 1000 - at.x) <= slack &&
        Math.abs(body.y / 1000 - at.y) <= slack
      )
    })
    if (i >= 0) this.pending.splice(i, 1)
  }

  /** The server refused input `seq` (not dropped it): forget it if it was a spawn. */
  refused(seq: number): void {
    const i = this.pending.findIndex((p) => p.seqs.includes(seq))
    if (i >= 0) this.pending.splice(i, 1)
  }

  /** A new world: spawns sent into the old one are gone with it. */
  clear(): void {
    this.pending.length = 0
  }

  /**
   * Spawns to send again now that the room is at `tick`, with a round trip of `rttTicks`: those
   * unconfirmed for RESEND_TICKS + rttTicks; spawns sent MAX_SENDS times are given up.
   */
  overdue(tick: number, rttTicks: number): SpawnCommand[] {
    const out: SpawnCommand[] = []
    for (let i = this.pending.length - 1; i >= 0; i--) {
      const p = this.pending[i]
      if (tick - p.sentTick <= RESEND_TICKS + rttTicks) continue
      if (p.sends >= MAX_SENDS) this.pending.splice(i, 1)
      else {
        p.sentTick = tick // in flight again: not due until sent() restarts its clock
        out.unshift(p.cmd)
      }
    }
    return out
  }
}
