/*
 * Checks for values that come from outside the engine (definitions, API arguments): each failure
 * throws a RangeError that names the value, so a bad input never reaches the simulation.
 */
import { MAX_POSITION } from './constants.ts'
import { TRIG_LIMIT, type Vec2 } from './math.ts'

/** A finite number, or a RangeError naming `what`. */
export function finite(what: string, value: number): number {
  if (typeof value !== 'number' || !Number.isFinite(value))
    throw new RangeError(`${what} must be a finite number, got ${value}`)
  return value
}

/** An angle the engine's sine and cosine take (|angle| < TRIG_LIMIT rad), or a RangeError naming `what`. */
export function angle(what: string, value: number): number {
  if (typeof value !== 'number' || !(value > -TRIG_LIMIT && value < TRIG_LIMIT))
    throw new RangeError(
      `${what} must be a finite number of radians in (-${TRIG_LIMIT}, ${TRIG_LIMIT}), got ${value}`,
    )
  return value
}

/** A world position within MAX_POSITION of the origin on each axis, or a RangeError naming `what`. */
export function position(what: string, v: Vec2): Vec2 {
  finiteVec(what, v)
  if (Math.abs(v.x) > MAX_POSITION || Math.abs(v.y) > MAX_POSITION)
    throw new RangeError(
      `${what} must lie within ${MAX_POSITION} m of the origin on each axis, got (${v.x}, ${v.y})`,
    )
  return v
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
