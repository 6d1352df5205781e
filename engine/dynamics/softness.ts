/*
 * Soft constraint coefficients (Erin Catto, "Soft Constraints", GDC 2011; Box2D v3 b2MakeSoft).
 * A constraint with stiffness `hertz` and damping ratio `zeta`, solved at time step h, applies
 *   impulse = -massScale * effectiveMass * (vn + biasRate * C) - impulseScale * accumulated
 * which is the implicit (stable at any stiffness) integration of a damped spring.
 */
import { TWO_PI } from '../math.ts'

/** The three coefficients of a soft constraint. */
export class Softness {
  biasRate = 0
  massScale = 1
  impulseScale = 0

  /** Sets the coefficients for stiffness `hertz` (Hz), damping ratio `zeta` and step `h` (s). */
  set(hertz: number, zeta: number, h: number): this {
    softnessInput[0] = hertz
    softnessInput[1] = zeta
    softnessInput[2] = h
    return this.setFromInput()
  }

  /**
   * `set` with its arguments in softnessInput (hertz, zeta, h): V8 boxes each double argument of a
   * call it does not inline (a heap number each), and the joints' prepare functions, inlined into
   * prepareJoints, can run out of its inlining budget (joint-math.ts setSpringSoftness).
   */
  setFromInput(): this {
    const hertz = softnessInput[0]
    const zeta = softnessInput[1]
    const h = softnessInput[2]
    if (hertz === 0) {
      this.biasRate = 0
      this.massScale = 1
      this.impulseScale = 0
      return this
    }
    const omega = TWO_PI * hertz
    const a1 = 2 * zeta + h * omega
    const a2 = h * omega * a1
    const a3 = 1 / (1 + a2)
    this.biasRate = omega / a1
    this.massScale = a2 * a3
    this.impulseScale = a3
    return this
  }
}

/** Input of Softness.setFromInput: stiffness (Hz), damping ratio, step (s). */
export const softnessInput = new Float64Array(3)
