/*
 * The snapshot timeline against an analytic trajectory: a body moving at constant velocity and
 * constant angular velocity, sent every other tick (30 Hz) with network jitter. Linear
 * interpolation of exact samples of a linear motion must reproduce the motion itself (up to the
 * 1 mm / 1/65536 turn quantization) at whatever tick is drawn, so the oracle is x(t) = v t.
 */
import { describe, expect, it } from 'vitest'
import { MAX_EXTRAPOLATION, type Pose, SnapshotTimeline } from '../../../client/net/interpolation.ts'
import { Prng } from '../../../engine/index.ts'
import { QuantizedFrame, quantizeAngle, quantizePosition, TICK_RATE } from '../../../shared/index.ts'

const V = 3 // m/s
const W = 5 // rad/s, several turns so angles wrap through +-pi
const MS_PER_TICK = 1000 / TICK_RATE

function frameAt(tick: number): QuantizedFrame {
  const f = new QuantizedFrame()
  const t = tick / TICK_RATE
  f.put(1, quantizePosition(V * t), quantizePosition(2), quantizeAngle(W * t), true)
  return f
}

const wrap = (a: number): number => Math.atan2(Math.sin(a), Math.cos(a))

/** Run a 60 Hz render loop over snapshots every 2 ticks; `lost` ticks are never delivered. */
function run(lost: Set<number>, jitterMs: number, seconds = 4) {
  const prng = new Prng(7)
  const timeline = new SnapshotTimeline(2)
  const latency = 40
  const arrivals: Array<{ tick: number; at: number }> = []
  for (let tick = 0; tick <= seconds * TICK_RATE; tick += 2) {
    if (lost.has(tick)) continue
    arrivals.push({ tick, at: tick * MS_PER_TICK + latency + prng.range(0, jitterMs) })
  }
  arrivals.sort((a, b) => a.at - b.at)
  const frames: Array<{ now: number; tick: number; newest: number; pose: Pose }> = []
  let next = 0
  for (let now = 0; now < seconds * 1000; now += MS_PER_TICK) {
    while (next < arrivals.length && arrivals[next].at <= now) {
      timeline.push(arrivals[next].tick, frameAt(arrivals[next].tick), arrivals[next].at)
      next++
    }
    const tick = timeline.advance(now)
    if (Number.isNaN(tick)) continue
    const pose = { x: 0, y: 0, angle: 0, awake: false }
    if (timeline.sample(1, tick, pose)) frames.push({ now, tick, newest: timeline.newestTick, pose })
  }
  return { frames, timeline }
}

describe('SnapshotTimeline', () => {
  it('reproduces constant-velocity motion at the drawn tick (linear positions, shortest-arc angles)', () => {
    const { frames } = run(new Set(), 8)
    const settled = frames.filter((f) => f.now > 1000)
    expect(settled.length).toBeGreaterThan(100)
    for (const f of settled) {
      const t = f.tick / TICK_RATE
      expect(Math.abs(f.pose.x - V * t)).toBeLessThan(0.002)
      expect(Math.abs(wrap(f.pose.angle - W * t))).toBeLessThan(0.001)
    }
  })

  it('settles on a delay of two to three snapshot intervals with light jitter', () => {
    const { timeline } = run(new Set(), 4)
    expect(timeline.delayTicks).toBeGreaterThanOrEqual(4)
    expect(timeline.delayTicks).toBeLessThanOrEqual(6.5)
  })

  it('grows the delay with jitter', () => {
    const calm = run(new Set(), 2).timeline.delayTicks
    const jittery = run(new Set(), 60).timeline.delayTicks
    expect(jittery).toBeGreaterThan(calm + 1)
  })

  it('neither pops nor freezes when one snapshot is lost', () => {
    const lost = new Set([120])
    const { frames } = run(lost, 4)
    const around = frames.filter((f) => f.tick > 112 && f.tick < 132)
    expect(around.length).toBeGreaterThan(10)
    for (let i = 1; i < around.length; i++) {
      const dx = around[i].pose.x - around[i - 1].pose.x
      // One 60 Hz frame at 3 m/s moves 5 cm; allow the 10 % clock slew and quantization.
      expect(dx).toBeGreaterThan(0.03)
      expect(dx).toBeLessThan(0.07)
    }
    for (const f of around) {
      expect(Math.abs(f.pose.x - (V * f.tick) / TICK_RATE)).toBeLessThan(0.002)
      // The delay covers the gap: it interpolates between held snapshots, never guessing ahead.
      expect(f.tick).toBeLessThanOrEqual(f.newest)
    }
  })

  it('extrapolates a bounded distance when snapshots stop, then holds', () => {
    const timeline = new SnapshotTimeline(2)
    for (let tick = 0; tick <= 60; tick += 2) timeline.push(tick, frameAt(tick), tick * MS_PER_TICK)
    const pose = { x: 0, y: 0, angle: 0, awake: false }
    timeline.sample(1, 63, pose)
    expect(pose.x).toBeCloseTo((V * 63) / TICK_RATE, 2)
    timeline.sample(1, 60 + 50, pose)
    expect(pose.x).toBeCloseTo((V * (60 + MAX_EXTRAPOLATION)) / TICK_RATE, 2)
  })
})
