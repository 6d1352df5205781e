/*
 * The fixed stepper: turns variable frame times into whole fixed steps (Glenn Fiedler, "Fix Your
 * Timestep!"). It lives outside World.step(), which always advances exactly 1/60 s. Catch-up is
 * capped: a frame longer than `maxFrame` counts as `maxFrame`, so a stalled tab or a debugger
 * pause cannot trigger a spiral of death. `alpha` is the fraction of a step left in the
 * accumulator, for interpolating the rendered state between the last two steps.
 */
import { STEP_SECONDS } from './constants.ts'

/** Accumulates frame time into whole fixed steps. */
export class FixedStepper {
  readonly step: number
  readonly maxFrame: number
  private accumulator = 0

  /** step: the fixed step (s), usually 1/60; maxFrame: the longest frame counted (s), usually 0.25. */
  constructor(step = STEP_SECONDS, maxFrame = 0.25) {
    if (!(step > 0) || !(maxFrame >= step))
      throw new RangeError(`invalid stepper: step ${step}, maxFrame ${maxFrame}`)
    this.step = step
    this.maxFrame = maxFrame
  }

  /** Adds a frame's duration (s) and returns how many whole steps to take now. */
  advance(frameSeconds: number): number {
    if (!(frameSeconds > 0)) return 0
    this.accumulator += Math.min(frameSeconds, this.maxFrame)
    let steps = 0
    // A small epsilon absorbs float error so 60 frames of 1/60 s give exactly 60 steps.
    while (this.accumulator >= this.step - 1e-9) {
      this.accumulator -= this.step
      steps++
    }
    if (this.accumulator < 0) this.accumulator = 0
    return steps
  }

  /** Fraction of a step in the accumulator, 0..1, for interpolation. */
  get alpha(): number {
    return this.accumulator / this.step
  }
}
