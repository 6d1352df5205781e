/*
 * Checks for values that come from outside the engine (definitions, API arguments): each failure
 * throws a RangeError that names the value, so a bad input never reaches the simulation.
 */
import type { Vec2 } from './math.ts'

/** A finite number, or a RangeError naming `what`. */
export function finite(what: string, value: number): number {
  if (typeof value !== 'number' || !Number.isFinite(value))
    throw new RangeError(`${what} must be a finite number, got ${value}`)
  return value
}

/** A vector of finite numbers, or a RangeError naming `what`. */
export function finiteVec(what: string, v: Vec2): Vec2 {
  if (v === null || typeof v !== 'object') throw new RangeError(`${what} must be a {x, y} vector, got ${v}`)
  // The names are built only for the error: a server calls this for every move of every grab
  // (setJointTarget), and building `${what}.x` allocated two strings per call.
  if (!Number.isFinite(v.x)) finite(`${what}.x`, v.x)
  if (!Number.isFinite(v.y)) finite(`${what}.y`, v.y)
  return v
}

/** A finite number in [lo, hi], or a RangeError naming `what`. */
export function inRange(what: string, value: number, lo: number, hi: number): number {
  finite(what, value)
  if (value < lo || value > hi) throw new RangeError(`${what} must be in [${lo}, ${hi}], got ${value}`)
  return value
}
