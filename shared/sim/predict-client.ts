/*
 * A predicting client: lockstep plus the player's own inputs applied at once.
 *
 * It keeps two simulations. The confirmed one (`sim`, the LockstepClient's) steps through the
 * server's stream as soon as it arrives and checks every hash checkpoint, exactly as a lockstep
 * client does. The present one runs ahead of it by `lead` ticks (the round trip measured from the
 * player's own inputs: how many ticks after it was sent an input shows up in the stream) and is
 * what the page draws. An own input is sent and applied to the present at once, as part of the
 * next present tick: that is the tick the client predicts the server will apply it at. The
 * game's own commands (`cmd`, e.g. the goal game's `kick`) are predicted the same way: they run in
 * the same simulation, so the present applies them at their predicted tick and the stream confirms
 * or corrects them like any input (room commands such as openScene are only sent).
 *
 * When ticks are confirmed, each is compared with what the present assumed for it (only the
 * player's own inputs, at their predicted ticks). If any differs (another player acted, or an own
 * input landed on another tick or was refused), the present is rolled back: it becomes a copy of
 * the confirmed state (the newest point known to be right) and is re-simulated to the present
 * tick with the own inputs not yet confirmed. Nothing ever reloads the page; the copies are
 * engine saves (sync-payload.ts cloneSimulation). Rollbacks, their depth and the re-simulation
 * time are counted for the HUD; predict-smoothing.ts hides the jumps they cause.
 */
import type { Command } from '../protocol/index.ts'
import { copyPlainData, type PlainData, type SimCommand } from './game.ts'
import { LockstepClient, type LockstepOptions } from './lockstep-client.ts'
import type { RoomSimulation } from './room-simulation.ts'
import { cloneSimulation } from './sync-payload.ts'
import { entryArguments, type StreamEntry } from './tick-stream.ts'

/** An own input not yet confirmed by the stream. */
interface PendingInput {
  /** Tick it was applied at in the present (re-assigned when it turns out late). */
  tick: number
  cmd: SimCommand
  /**
   * The server's tick as estimated when it was sent (for the lead measurement): the playout's
   * smooth estimate, not the newest tick received, which lags by up to the hold when idle.
   */
  sentAt: number
  /** Time it was sent (ms), to drop inputs the server refused. */
  time: number
}

/** Options beyond the lockstep client's. */
export interface PredictOptions extends LockstepOptions {
  /** Clock for re-simulation timings (ms), performance.now in the page. */
  clock?: () => number
  /**
   * Called during a rollback with the old present and the corrected one at the same tick
   * (smoothing keeps what was drawn); not called when the old present was behind the confirmed tick.
   */
  onRollback?(before: RoomSimulation, after: RoomSimulation): void
}

/** Rollback figures for the HUD. */
export interface PredictStats {
  rollbacks: number
  /** Rollbacks in the last full second. */
  rollbacksPerSecond: number
  /** Depth of the last rollback (ticks re-simulated). */
  lastDepth: number
  maxDepth: number
  /** Re-simulation time of the last advance (ms) and its smoothed value. */
  resimMs: number
  resimMsSmoothed: number
  /** Own inputs confirmed, and those that landed on another tick than predicted. */
  confirmed: number
  mispredicted: number
}

/** Inputs older than this without confirmation were refused by the server (ms). */
const FORGET_AFTER_MS = 3000
/** Largest lead (ticks): half a second. */
const MAX_LEAD = 30
/**
 * Empty ticks the server may hold back for a predicting client (join.hold): its present runs
 * ahead assuming nobody else acts, which an empty run only confirms, so it may wait as long as the
 * present may lead; the confirmed state then lags the server by at most half a second when idle.
 */
export const PREDICT_HOLD = MAX_LEAD

const sameAction = (a: SimCommand, b: StreamEntry['action']): boolean =>
  a.k === b.k && JSON.stringify(entryArguments(a)) === JSON.stringify(entryArguments(b))

/** The predicting client (see the file comment). */
export class PredictClient extends LockstepClient {
  present: RoomSimulation | null = null
  /** Ticks the present runs ahead of the newest confirmed tick. */
  lead = 4
  readonly predict: PredictStats = {
    rollbacks: 0,
    rollbacksPerSecond: 0,
    lastDepth: 0,
    maxDepth: 0,
    resimMs: 0,
    resimMsSmoothed: 0,
    confirmed: 0,
    mispredicted: 0,
  }
  private pending: PendingInput[] = []
  private dirty = false
  private leadSample = 4
  private secondStart = 0
  private rollbacksThisSecond = 0
  private seq = 0
  private readonly clock: () => number

  constructor(protected readonly predictOptions: PredictOptions) {
    super({
      hold: PREDICT_HOLD,
      ...predictOptions,
      playout: { minDelay: 0, ...predictOptions.playout },
    })
    this.clock = predictOptions.clock ?? (() => 0)
  }

  /** This player's game view as the present (what the page draws) has it; else the confirmed one. */
  override view(): PlainData | undefined {
    return (this.present ?? this.sim)?.playerView(this.playerId)
  }

  /** Send an own input and apply it to the present at once; returns its sequence number. */
  input(cmd: Command, nowMs: number): number {
    const seq = ++this.seq
    this.options.send({ t: 'input', seq, cmd })
    if (cmd.k !== 'inspect') this.predictOwn(cmd, nowMs)
    return seq
  }

  /**
   * Send an own game command (`cmd`: its kind and arguments) and, when the room's game lists that
   * kind, apply it to the present at once, as input() does; returns its sequence number.
   */
  gameCommand(kind: string, args: { [key: string]: PlainData }, nowMs: number): number {
    const seq = ++this.seq
    this.options.send({ t: 'cmd', seq, k: kind, a: args })
    const game = this.present?.game
    if (game && Object.hasOwn(game.commands, kind) && !game.commands[kind].builtin)
      this.predictOwn({ k: 'cmd', kind, a: copyPlainData(args) }, nowMs)
    return seq
  }

  /** Apply an own command to the present at its next tick and remember it until confirmed. */
  private predictOwn(cmd: SimCommand, nowMs: number): void {
    if (!this.present || this.state !== 'running') return
    const tick = this.present.tick + 1
    this.applyOwn(this.present, cmd)
    this.pending.push({ tick, cmd, sentAt: Math.floor(this.playout.estimate(nowMs)), time: nowMs })
  }

  /**
   * Step the confirmed simulation through what was received (see confirmGoal), then bring the
   * present up to date; returns the confirmed ticks stepped.
   */
  override advance(nowMs: number): number {
    if (this.state !== 'running' || !this.sim) return 0
    let n = 0
    const goal = this.confirmGoal()
    while (this.state === 'running' && this.sim.tick < goal) {
      const tick = this.sim.tick + 1
      this.confirmTick(tick)
      this.stepTick()
      n++
    }
    if (this.state !== 'running') return n
    this.forgetRefused(nowMs)
    const target = Math.max(this.sim.tick, Math.floor(this.playout.estimate(nowMs)) + this.lead)
    const start = this.clock()
    let resimulated = 0
    if (this.dirty || !this.present || this.present.tick < this.sim.tick) {
      resimulated = this.rollback(target)
    } else {
      for (let k = 0; k < MAX_LEAD && this.present.tick < target; k++) this.present.runTick()
    }
    this.predict.resimMs = resimulated > 0 ? this.clock() - start : 0
    this.predict.resimMsSmoothed = this.predict.resimMsSmoothed * 0.9 + this.predict.resimMs * 0.1
    if (nowMs - this.secondStart >= 1000) {
      this.predict.rollbacksPerSecond = this.rollbacksThisSecond
      this.rollbacksThisSecond = 0
      this.secondStart = nowMs
    }
    return n
  }

  /**
   * The tick to step the confirmed simulation to in this frame. Everything received when it may
   * change the present: entries not yet stepped (anyone's command), own inputs predicted for a
   * received tick, a rollback due. Otherwise the backlog is only empty ticks, which the present
   * already assumed: a held run (join.hold, up to 30 ticks at once) is spread over the next frames,
   * an eighth of the backlog and at least 2 ticks a frame, so a frame steps 4 confirmed ticks at
   * most instead of 30 and the backlog is gone well before the next run arrives.
   */
  private confirmGoal(): number {
    const sim = this.sim as RoomSimulation
    const newest = this.newestTick
    const backlog = newest - sim.tick
    if (backlog <= 2 || this.dirty || this.head < this.entries.length) return newest
    if (this.pending.some((p) => p.tick <= newest)) return newest
    return sim.tick + Math.max(2, Math.ceil(backlog / 8))
  }

  protected override restored(sim: RoomSimulation): void {
    this.present = null
    this.pending = []
    this.dirty = true
    super.restored(sim)
  }

  /** Compare confirmed tick `tick` with what the present assumed, and settle own inputs. */
  private confirmTick(tick: number): void {
    const confirmed: StreamEntry[] = []
    for (let i = this.head; i < this.entries.length && this.entries[i].tick === tick; i++) {
      confirmed.push(this.entries[i])
    }
    const assumed = this.pending.filter((p) => p.tick === tick)
    let same = confirmed.length === assumed.length
    for (let i = 0; same && i < confirmed.length; i++) {
      same = confirmed[i].player === this.playerId && sameAction(assumed[i].cmd, confirmed[i].action)
    }
    for (const e of confirmed) if (e.player === this.playerId) this.settleOwn(e, tick)
    for (const p of this.pending) {
      if (p.tick <= tick) {
        // Not confirmed at the tick it was predicted for: it will land later (or was refused).
        p.tick = tick + 1
        this.predict.mispredicted++
        same = false
      }
    }
    if (!same) this.dirty = true
  }

  /** An own entry in the stream: drop it (and moves the server merged into it) from the pending list. */
  private settleOwn(e: StreamEntry, tick: number): void {
    const i = this.pending.findIndex((p) => sameAction(p.cmd, e.action))
    if (i < 0) return
    const p = this.pending[i]
    this.leadSample = this.leadSample * 0.8 + (tick - p.sentAt) * 0.2
    this.lead = Math.min(MAX_LEAD, Math.max(1, Math.ceil(this.leadSample + 1)))
    // The server applies a player's inputs in order: earlier ones still pending were refused, or
    // were moves it replaced with a later one of the same tick.
    this.pending = this.pending.slice(i + 1)
    this.predict.confirmed++
  }

  private forgetRefused(nowMs: number): void {
    const before = this.pending.length
    this.pending = this.pending.filter((p) => nowMs - p.time < FORGET_AFTER_MS)
    if (this.pending.length !== before) this.dirty = true
  }

  /** Replace the present with the confirmed state and re-simulate to `target`; returns the depth. */
  private rollback(target: number): number {
    const confirmed = this.sim as RoomSimulation
    const rules = this.rules
    if (!rules) return 0
    const before = this.present
    const present = cloneSimulation(confirmed, {
      maxBodies: rules.maxBodies,
      // This player's own predictions: its room controls are refused when it has no rights.
      controls: rules.controls,
      name: '',
    })
    const depth = Math.max(0, target - present.tick)
    let compared = false
    for (let t = present.tick + 1; t <= target; t++) {
      for (const p of this.pending) if (p.tick === t) this.applyOwn(present, p.cmd)
      present.runTick()
      // The old present at the same tick is what the smoothing compares with.
      if (before && !compared && present.tick === before.tick) {
        this.predictOptions.onRollback?.(before, present)
        compared = true
      }
    }
    this.present = present
    this.dirty = false
    if (before) {
      this.predict.rollbacks++
      this.rollbacksThisSecond++
      this.predict.lastDepth = depth
      this.predict.maxDepth = Math.max(this.predict.maxDepth, depth)
    }
    return Math.max(1, depth)
  }

  private applyOwn(sim: RoomSimulation, cmd: SimCommand): void {
    if (cmd.k !== 'inspect') sim.apply(this.playerId, cmd)
  }
}
