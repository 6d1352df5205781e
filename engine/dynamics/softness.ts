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
