/*
 * Changing a joint's settings after creation (World.setJointSettings). One call takes any of the
 * settings the joint's kind has, by the names its definition uses (RevoluteJointDef's lowerAngle,
 * WheelJointDef's maxMotorTorque, ...), checks every given value exactly as createJoint checks it
 * (the same ranges, the same RangeError naming the field), checks the combination (lower <= upper,
 * minLength <= length <= maxLength) against the joint's current values for the fields not given,
 * and only then writes: a refused call changes nothing.
 *
 * Warm starting follows Box2D v3.1's setters (revolute_joint.c, prismatic_joint.c, wheel_joint.c,
 * distance_joint.c): the accumulated impulses are kept, except that toggling a limit or changing
 * its bounds zeroes the limit impulses (b2RevoluteJoint_EnableLimit/SetLimits), toggling a motor
 * zeroes the motor impulse, toggling a spring zeroes the spring impulse, and changing a distance
 * joint's length or range zeroes its axial and limit impulses (b2DistanceJoint_SetLength,
 * SetLengthRange). Nothing else is touched (the frames, the reference angle, collideConnected,
 * which are fixed at creation), so the joint's saved and hashed state changes only by its
 * settings. Allocation-free for a valid call (the checks build strings only to throw).
 */

import { finite, inRange } from '../def-checks.ts'
import type { JointSettings } from '../types.ts'
import type { Joint } from './joint.ts'
import { DISTANCE, JOINT_TYPE_NAMES, MOUSE, REVOLUTE, WELD } from './joint-math.ts'

/** The settings each joint kind takes (World.setJointSettings), by kind name. */
export const JOINT_SETTINGS = {
  revolute: [
    'enableLimit',
    'lowerAngle',
    'upperAngle',
    'enableMotor',
    'motorSpeed',
    'maxMotorTorque',
    'enableSpring',
    'hertz',
    'dampingRatio',
    'targetAngle',
    'breakForce',
    'breakTorque',
  ],
  distance: [
    'length',
    'minLength',
    'maxLength',
    'hertz',
    'dampingRatio',
    'enableMotor',
    'motorSpeed',
    'maxMotorForce',
    'breakForce',
    'breakTorque',
  ],
  mouse: ['maxForce', 'hertz', 'dampingRatio', 'breakForce', 'breakTorque'],
  weld: [
    'linearHertz',
    'angularHertz',
    'linearDampingRatio',
    'angularDampingRatio',
    'breakForce',
    'breakTorque',
  ],
  prismatic: [
    'enableLimit',
    'lower',
    'upper',
    'enableMotor',
    'motorSpeed',
    'maxMotorForce',
    'enableSpring',
    'hertz',
    'dampingRatio',
    'targetTranslation',
    'breakForce',
    'breakTorque',
  ],
  wheel: [
    'enableLimit',
    'lower',
    'upper',
    'enableMotor',
    'motorSpeed',
    'maxMotorTorque',
    'enableSpring',
    'hertz',
    'dampingRatio',
    'breakForce',
    'breakTorque',
  ],
  motor: ['maxForce', 'maxTorque', 'correctionFactor', 'breakForce', 'breakTorque'],
} as const satisfies Record<string, ReadonlyArray<keyof JointSettings>>

/** JOINT_SETTINGS as sets, indexed by kind code (joint-math.ts). */
const KIND_SETTINGS: ReadonlyArray<ReadonlySet<string>> = (() => {
  const out: Set<string>[] = []
  for (let code = 0; code < JOINT_TYPE_NAMES.length; code++) {
    out[code] = new Set(JOINT_SETTINGS[JOINT_TYPE_NAMES[code] as keyof typeof JOINT_SETTINGS])
  }
  return out
})()

/** Farthest translation limit and longest length (m): joint-defs.ts's MAX_JOINT_REACH. */
const REACH = 1e6
/** Shortest distance joint (m): joint-defs.ts's MIN_JOINT_LENGTH. */
const MIN_LENGTH = 0.001

/**
 * Checks `s` against joint `j` (id `id` for the messages) and writes it; throws a RangeError
 * naming the first bad field and changes nothing then.
 */
export function applyJointSettings(j: Joint, id: number, s: JointSettings): void {
  if (s === null || typeof s !== 'object') throw new RangeError(`joint settings must be an object, got ${s}`)
  const allowed = KIND_SETTINGS[j.type]
  for (const key in s) {
    if (!allowed.has(key)) {
      throw new RangeError(
        `${key} is not a setting of joint ${id}, a ${JOINT_TYPE_NAMES[j.type]} joint (it has ${[...allowed].join(', ')})`,
      )
    }
  }
  // 1. Check: every value as createJoint checks it, combinations against the current values. The
  // checks are written out rather than called: a double passed to a call V8 does not inline is
  // boxed, and this function calls too many checks for all of them to be inlined.
  const type = j.type
  const breakForce = s.breakForce ?? j.breakForce
  if (!(typeof breakForce === 'number' && breakForce >= 0)) threshold('breakForce', breakForce)
  const breakTorque = s.breakTorque ?? j.breakTorque
  if (!(typeof breakTorque === 'number' && breakTorque >= 0)) threshold('breakTorque', breakTorque)
  const enableLimit = s.enableLimit ?? j.enableLimit
  if (typeof enableLimit !== 'boolean') notBoolean('enableLimit', enableLimit)
  const enableMotor = s.enableMotor ?? j.enableMotor
  if (typeof enableMotor !== 'boolean') notBoolean('enableMotor', enableMotor)
  const enableSpring = s.enableSpring ?? j.enableSpring
  if (typeof enableSpring !== 'boolean') notBoolean('enableSpring', enableSpring)
  const motorSpeed = s.motorSpeed ?? j.motorSpeed
  if (!(typeof motorSpeed === 'number' && motorSpeed - motorSpeed === 0)) finite('motorSpeed', motorSpeed)
  const maxMotorTorque = s.maxMotorTorque ?? j.maxMotorTorque
  if (!within(maxMotorTorque, 0, 1e12)) inRange('maxMotorTorque', maxMotorTorque, 0, 1e12)
  const maxMotorForce = s.maxMotorForce ?? j.maxMotorForce
  if (!within(maxMotorForce, 0, 1e12)) inRange('maxMotorForce', maxMotorForce, 0, 1e12)
  // A weld's linear spring is the joint's hertz and dampingRatio under the definition's names.
  const weld = type === WELD
  const springHi = type === MOUSE ? 1000 : 1e6
  const hertz = (weld ? s.linearHertz : s.hertz) ?? j.hertz
  if (!within(hertz, 0, springHi)) inRange(weld ? 'linearHertz' : 'hertz', hertz, 0, springHi)
  const dampingRatio = (weld ? s.linearDampingRatio : s.dampingRatio) ?? j.dampingRatio
  if (!within(dampingRatio, 0, springHi))
    inRange(weld ? 'linearDampingRatio' : 'dampingRatio', dampingRatio, 0, springHi)
  const lowerA = s.lowerAngle ?? j.lowerAngle
  if (!within(lowerA, -Math.PI, Math.PI)) inRange('lowerAngle', lowerA, -Math.PI, Math.PI)
  const upperA = s.upperAngle ?? j.upperAngle
  if (!within(upperA, -Math.PI, Math.PI)) inRange('upperAngle', upperA, -Math.PI, Math.PI)
  if (upperA < lowerA) order('upperAngle', upperA, 'lowerAngle', lowerA)
  const lowerT = s.lower ?? j.lowerTranslation
  if (!within(lowerT, -REACH, REACH)) inRange('lower', lowerT, -REACH, REACH)
  const upperT = s.upper ?? j.upperTranslation
  if (!within(upperT, -REACH, REACH)) inRange('upper', upperT, -REACH, REACH)
  if (upperT < lowerT) order('upper', upperT, 'lower', lowerT)
  const target = type === REVOLUTE ? s.targetAngle : s.targetTranslation
  const springTarget = target ?? j.springTarget
  const targetHi = type === REVOLUTE ? Math.PI : REACH
  if (!within(springTarget, -targetHi, targetHi))
    inRange(type === REVOLUTE ? 'targetAngle' : 'targetTranslation', springTarget, -targetHi, targetHi)
  let length = j.length
  let minLength = j.minLength
  let maxLength = j.maxLength
  if (type === DISTANCE) {
    length = s.length ?? j.length
    if (!within(length, MIN_LENGTH, REACH)) inRange('length', length, MIN_LENGTH, REACH)
    // A limit not given that equalled the old length follows the new one (a rod stays a rod, a
    // spring without limits stays without), as createJoint's defaults (min = max = length) do.
    minLength = s.minLength ?? (j.minLength === j.length ? length : j.minLength)
    if (!within(minLength, 0, length)) inRange('minLength', minLength, 0, length)
    maxLength = s.maxLength ?? (j.maxLength === j.length ? length : j.maxLength)
    if (!within(maxLength, length, REACH)) inRange('maxLength', maxLength, length, REACH)
  }
  const angularHertz = s.angularHertz ?? j.angularHertz
  if (!within(angularHertz, 0, 1e6)) inRange('angularHertz', angularHertz, 0, 1e6)
  const angularDampingRatio = s.angularDampingRatio ?? j.angularDampingRatio
  if (!within(angularDampingRatio, 0, 1e6)) inRange('angularDampingRatio', angularDampingRatio, 0, 1e6)
  const maxForce = s.maxForce ?? j.maxForce
  if (!within(maxForce, 0, 1e12)) inRange('maxForce', maxForce, 0, 1e12)
  const maxTorque = s.maxTorque ?? j.maxTorque
  if (!within(maxTorque, 0, 1e12)) inRange('maxTorque', maxTorque, 0, 1e12)
  const correctionFactor = s.correctionFactor ?? j.correctionFactor
  if (!within(correctionFactor, 0, 1)) inRange('correctionFactor', correctionFactor, 0, 1)

  // 2. Warm starting as Box2D's setters leave it.
  if (enableLimit !== j.enableLimit || lowerA !== j.lowerAngle || upperA !== j.upperAngle) {
    j.lowerImpulse = 0
    j.upperImpulse = 0
  }
  if (lowerT !== j.lowerTranslation || upperT !== j.upperTranslation) {
    j.lowerImpulse = 0
    j.upperImpulse = 0
  }
  if (length !== j.length || minLength !== j.minLength || maxLength !== j.maxLength) {
    j.impulse = 0
    j.lowerImpulse = 0
    j.upperImpulse = 0
  }
  if (enableMotor !== j.enableMotor) j.motorImpulse = 0
  if (enableSpring !== j.enableSpring) j.springImpulse = 0

  // 3. Write.
  j.breakForce = breakForce
  j.breakTorque = breakTorque
  j.enableLimit = enableLimit
  j.enableMotor = enableMotor
  j.enableSpring = enableSpring
  j.motorSpeed = motorSpeed
  j.maxMotorTorque = maxMotorTorque
  j.maxMotorForce = maxMotorForce
  j.hertz = hertz
  j.dampingRatio = dampingRatio
  j.lowerAngle = lowerA
  j.upperAngle = upperA
  j.lowerTranslation = lowerT
  j.upperTranslation = upperT
  j.length = length
  j.minLength = minLength
  j.maxLength = maxLength
  j.springTarget = springTarget
  j.angularHertz = angularHertz
  j.angularDampingRatio = angularDampingRatio
  j.maxForce = maxForce
  j.maxTorque = maxTorque
  j.correctionFactor = correctionFactor
}

/** Whether `v` is a number in [lo, hi] (NaN is not). */
function within(v: number, lo: number, hi: number): boolean {
  return typeof v === 'number' && v >= lo && v <= hi
}

function notBoolean(name: string, value: unknown): never {
  throw new RangeError(`${name} must be a boolean, got ${String(value)}`)
}

/** A break threshold: a number >= 0 (Infinity: never), as createJoint takes it. */
function threshold(name: string, value: number): number {
  if (typeof value !== 'number' || !(value >= 0))
    throw new RangeError(`${name} must be a number >= 0 (Infinity: never breaks), got ${value}`)
  return value
}

function order(upper: string, u: number, lower: string, l: number): never {
  throw new RangeError(`${upper} must be >= ${lower} (${l}), got ${u}`)
}
