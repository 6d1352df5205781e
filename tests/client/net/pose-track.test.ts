/*
 * A body left out of most snapshots by the byte budget, against the analytic free fall
 * y(t) = -g t^2 / 2: the server writes it only every 8th tick, the page draws every tick 6 ticks
 * behind the newest snapshot. Drawn from the track, the body moves on every frame, never by much
 * more than the true per-tick fall, and stays within a few centimetres of the true path; when
 * samples stop it is extrapolated for MAX_AHEAD ticks and then held.
 */
import { describe, expect, it } from 'vitest'
import { MAX_AHEAD, PoseTrack } from '../../../client/net/pose-track.ts'

const G = 10
const trueY = (tick: number): number => (-G / 2) * (tick / 60) ** 2

describe('PoseTrack', () => {
  it('moves a budget-starved falling body on every frame, close to the true path, without pops', () => {
    const track = new PoseTrack()
    const pose = { x: 0, y: 0, angle: 0, awake: false }
    let prev = Number.NaN
    let worstStep = 0
    let worstError = 0
    let still = 0
    for (let now = 0; now <= 240; now++) {
      const render = now - 6
      if (now % 8 === 0) track.add(now, 0, trueY(now), 0, true, render)
      track.decay(1000 / 60)
      if (render < 16 || !track.sample(render, pose)) continue
      if (!Number.isNaN(prev)) {
        const step = prev - pose.y
        if (step <= 0) still++
        // The true fall in one tick at this time, with room for the blended corrections.
        worstStep = Math.max(worstStep, step / (trueY(render - 1) - trueY(render)))
      }
      worstError = Math.max(worstError, Math.abs(pose.y - trueY(render)))
      prev = pose.y
    }
    expect(still).toBe(0)
    expect(worstStep).toBeLessThan(1.6)
    expect(worstError).toBeLessThan(0.05)
  })

  it('blends a correction in over time instead of jumping to it', () => {
    const track = new PoseTrack()
    const pose = { x: 0, y: 0, angle: 0, awake: false }
    track.add(0, 0, 0, 0, true, Number.NaN)
    track.add(2, 0.1, 0, 0, true, Number.NaN)
    // Drawn at tick 10 the body is extrapolated to x = 0.5; the server then says it stopped at 0.2.
    track.sample(10, pose)
    expect(pose.x).toBeCloseTo(0.5, 9)
    track.add(4, 0.2, 0, 0, false, 10)
    track.sample(10, pose)
    expect(pose.x).toBeCloseTo(0.5, 9)
    track.decay(1000)
    track.sample(10, pose)
    expect(pose.x).toBeCloseTo(0.2, 3)
  })

  it(`extrapolates at most ${MAX_AHEAD} ticks past the newest sample, then holds`, () => {
    const track = new PoseTrack()
    const pose = { x: 0, y: 0, angle: 0, awake: false }
    track.add(0, 0, 0, 0, true, Number.NaN)
    track.add(2, 0.2, 0, 0, true, Number.NaN)
    track.sample(2 + MAX_AHEAD + 100, pose)
    expect(pose.x).toBeCloseTo(0.2 + 0.1 * MAX_AHEAD, 9)
  })

  it('turns the short way through +-pi', () => {
    const track = new PoseTrack()
    const pose = { x: 0, y: 0, angle: 0, awake: false }
    track.add(0, 0, 0, Math.PI - 0.1, true, Number.NaN)
    track.add(2, 0, 0, -Math.PI + 0.1, true, Number.NaN)
    track.sample(1, pose)
    expect(Math.abs(Math.abs(pose.angle) - Math.PI)).toBeLessThan(1e-9)
  })
})
