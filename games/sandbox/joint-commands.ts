/*
 * The sandbox's joint commands (issues 28 and 31): the Build "Joints" tools as game commands with
 * JSON Schema arguments. `weld` glues two bodies (or a body to the background, a = 0), `hinge` is
 * a pin with optional limits and motor, `spring` a soft distance joint, `slider` a prismatic joint
 * and `wheel` a sprung wheel joint with a motor (a car is a chassis and two wheels); every one
 * takes a breaking force and torque; each is undoable (undo-commands.ts). `jointMotor` sets a joint's motor speed, for the player who
 * made the joint only (the rule every replica applies, so keys drive only your own machine).
 * `editJoint` changes an existing joint's settings (the Edit tool's joint panel), by the names of
 * its wire form (WireJoint: limit, lower, upper, motor, speed, torque, force, spring, hz, damping,
 * target, ahz, adamping, length, min, max, correction, breakForce, breakTorque), for the joint's
 * maker and for the scene's joints; undoable (undo rebuilds the joint as it was, with a new id).
 *
 * The schemas bound every number (the ranges are PROTOCOL.md's, "The sandbox's joint commands");
 * what a schema cannot say (upper below lower, a zero axis) is refused in apply, naming the
 * fields. Anchors are clamped to the world square like a pin's; each must lie within its body's
 * reach plus ANCHOR_MARGIN (shared/sim's createUserJoint).
 */
import { circle, type JointSettings, type Vec2 } from '../../engine/index.ts'
import {
  anchorRefusal,
  clampToWorld,
  type GameContext,
  MAX_ROPE_LENGTH,
  NO_ITEMS,
  type WireJoint,
  type WireJointDef,
  type WireJointKind,
} from '../../shared/index.ts'
import type { GameCommandDefinition } from '../game-api.ts'
import { captureBodies, captureJoints, recordAction, recordJoint } from './undo-commands.ts'

/** Fastest motor a player may ask for: rad/s for hinges and wheels, m/s for sliders. */
export const MAX_JOINT_MOTOR_SPEED = 50
/** Largest motor torque (N m) or force (N) a player may ask for. */
export const MAX_JOINT_MOTOR_EFFORT = 1e6
/** Stiffest player spring (Hz): a spring near the 240 Hz sub-step rate is a rod that rings. */
export const MAX_JOINT_HERTZ = 60
/** Largest damping ratio of a player's spring. */
export const MAX_JOINT_DAMPING = 10
/** Largest breaking force (N) or torque (N m) a player may set (absent: never breaks). */
export const MAX_BREAK = 1e9
/** Farthest a slider or wheel limit may be from where it starts (m). */
export const MAX_SLIDER_TRAVEL = 100

const coordinate = { type: 'number', minimum: -1e6, maximum: 1e6 }
const bodies = {
  a: { type: 'integer', minimum: 0, maximum: Number.MAX_SAFE_INTEGER },
  b: { type: 'integer', minimum: 1, maximum: Number.MAX_SAFE_INTEGER },
}
const breaking = {
  breakForce: { type: 'number', exclusiveMinimum: 0, maximum: MAX_BREAK },
  breakTorque: { type: 'number', exclusiveMinimum: 0, maximum: MAX_BREAK },
}
const spring = {
  hz: { type: 'number', minimum: 0, maximum: MAX_JOINT_HERTZ },
  damping: { type: 'number', minimum: 0, maximum: MAX_JOINT_DAMPING },
}
const speed = { type: 'number', minimum: -MAX_JOINT_MOTOR_SPEED, maximum: MAX_JOINT_MOTOR_SPEED }
const effort = { type: 'number', exclusiveMinimum: 0, maximum: MAX_JOINT_MOTOR_EFFORT }
const travel = { type: 'number', minimum: -MAX_SLIDER_TRAVEL, maximum: MAX_SLIDER_TRAVEL }
const angle = { type: 'number', minimum: -Math.PI, maximum: Math.PI }

/** The settings `editJoint` takes for each wire kind (WireJoint field names). */
export const EDITABLE_JOINT_SETTINGS: Record<WireJointKind, readonly string[]> = (() => {
  const brk = ['breakForce', 'breakTorque']
  const distance = ['length', 'min', 'max', 'hz', 'damping', 'motor', 'speed', 'force', ...brk]
  const slide = ['limit', 'lower', 'upper', 'motor', 'speed']
  return {
    pin: [...slide, 'torque', 'spring', 'hz', 'damping', 'target', ...brk],
    rod: distance,
    rope: distance,
    spring: distance,
    weld: ['hz', 'damping', 'ahz', 'adamping', ...brk],
    slider: [...slide, 'force', 'spring', 'hz', 'damping', 'target', ...brk],
    wheel: [...slide, 'torque', 'spring', 'hz', 'damping', ...brk],
    motor: ['force', 'torque', 'correction', ...brk],
  }
})()

/** editJoint's arguments: the joint and any of the WireJoint settings its kind has. */
export interface EditJointArgs {
  joint: number
  limit?: boolean
  lower?: number
  upper?: number
  motor?: boolean
  speed?: number
  torque?: number
  force?: number
  spring?: boolean
  hz?: number
  damping?: number
  target?: number
  ahz?: number
  adamping?: number
  length?: number
  min?: number
  max?: number
  correction?: number
  breakForce?: number
  breakTorque?: number
}

/** The engine's name of each wire setting, by the engine's joint type (see the file comment). */
function engineName(type: WireJointDef['type'], field: string): keyof JointSettings {
  switch (field) {
    case 'limit':
      return 'enableLimit'
    case 'motor':
      return 'enableMotor'
    case 'spring':
      return 'enableSpring'
    case 'speed':
      return 'motorSpeed'
    case 'lower':
      return type === 'revolute' ? 'lowerAngle' : 'lower'
    case 'upper':
      return type === 'revolute' ? 'upperAngle' : 'upper'
    case 'target':
      return type === 'revolute' ? 'targetAngle' : 'targetTranslation'
    case 'torque':
      return type === 'motor' ? 'maxTorque' : 'maxMotorTorque'
    case 'force':
      return type === 'motor' ? 'maxForce' : 'maxMotorForce'
    case 'hz':
      return type === 'weld' ? 'linearHertz' : 'hertz'
    case 'damping':
      return type === 'weld' ? 'linearDampingRatio' : 'dampingRatio'
    case 'ahz':
      return 'angularHertz'
    case 'adamping':
      return 'angularDampingRatio'
    case 'min':
      return 'minLength'
    case 'max':
      return 'maxLength'
    case 'correction':
      return 'correctionFactor'
    default:
      return field as keyof JointSettings // length, breakForce, breakTorque
  }
}

/** The engine joint type of a wire kind. */
function engineType(kind: WireJointKind): WireJointDef['type'] {
  if (kind === 'pin') return 'revolute'
  if (kind === 'slider') return 'prismatic'
  if (kind === 'rod' || kind === 'rope' || kind === 'spring') return 'distance'
  return kind
}

/**
 * editJoint's settings for the engine (World.setJointSettings), or why they are refused: a setting
 * the joint's kind lacks, a pin's angle beyond +-pi, lower above upper, or a length outside
 * [min, max] (a limit not given that equals the length follows a new length, as the engine does).
 */
export function editJointSettings(j: Readonly<WireJoint>, c: EditJointArgs): JointSettings | string {
  const allowed = EDITABLE_JOINT_SETTINGS[j.kind]
  const given = Object.keys(c).filter((k) => k !== 'joint')
  if (given.length === 0) return 'editJoint refused: give at least one setting'
  for (const key of given)
    if (!allowed.includes(key))
      return `editJoint refused: a ${j.kind} joint has no ${key} (its settings: ${allowed.join(', ')})`
  if (j.kind === 'pin')
    for (const key of ['lower', 'upper', 'target'] as const) {
      const v = c[key]
      if (v !== undefined && Math.abs(v) > Math.PI)
        return `editJoint refused: a pin's ${key} must be within +-pi rad, got ${v}`
    }
  const lower = c.lower ?? j.lower
  const upper = c.upper ?? j.upper
  if (lower > upper) return `editJoint refused: lower (${lower}) must not be above upper (${upper})`
  const length = c.length ?? j.length
  const min = c.min ?? (j.min === j.length ? length : j.min)
  const max = c.max ?? (j.max === j.length ? length : j.max)
  if (min > length) return `editJoint refused: min (${min}) must not be above length (${length})`
  if (max < length) return `editJoint refused: max (${max}) must not be below length (${length})`
  const type = engineType(j.kind)
  const out: Record<string, number | boolean> = {}
  for (const key of given) {
    const v = c[key as keyof EditJointArgs] as number | boolean
    // A break threshold of 0 is "never", as on the wire.
    out[engineName(type, key)] = (key === 'breakForce' || key === 'breakTorque') && v === 0 ? Infinity : v
  }
  return out as JointSettings
}

/** Why `player` may not edit joint `id` (missing, or another player's), or null. */
function editJointRefusal(ctx: GameContext<undefined>, player: number, id: number): string | null {
  const j = ctx.userJoint(id)
  if (!j) return `joint ${id} is not a joint in this room`
  if (j.owner !== 0 && j.owner !== player)
    return `joint ${id} belongs to player ${j.owner}: only its maker may edit it`
  return null
}

/** An object schema with these properties, the required ones, and nothing else. */
const args = (properties: Record<string, object>, required: string[]) =>
  ({ type: 'object', properties, required, additionalProperties: false }) as const

interface JointArgs {
  a: number
  b: number
  breakForce?: number
  breakTorque?: number
}
interface PointArgs extends JointArgs {
  x: number
  y: number
}
interface WeldArgs extends PointArgs {
  hz?: number
  damping?: number
}
interface HingeArgs extends PointArgs {
  lower?: number
  upper?: number
  speed?: number
  torque?: number
}
interface SpringArgs extends JointArgs {
  ax: number
  ay: number
  bx: number
  by: number
  hz: number
  damping?: number
  length?: number
}
interface SliderArgs extends PointArgs {
  dx: number
  dy: number
  lower?: number
  upper?: number
  speed?: number
  force?: number
  hz?: number
  damping?: number
}
interface WheelArgs {
  a: number
  b?: number
  radius?: number
  breakForce?: number
  breakTorque?: number
  x?: number
  y?: number
  dx?: number
  dy?: number
  lower?: number
  upper?: number
  hz?: number
  damping?: number
  speed?: number
  torque?: number
}

/** Bodies and breaking thresholds of a definition (a = 0: the world). */
const common = (c: JointArgs | (WheelArgs & { b: number })) => ({
  bodyA: c.a === 0 ? null : c.a,
  bodyB: c.b,
  breakForce: c.breakForce,
  breakTorque: c.breakTorque,
})

/** The limit [lower, upper] when either is given (a missing one is 0), or why it is refused. */
function limits(c: { lower?: number; upper?: number }): { lower: number; upper: number } | string | null {
  if (c.lower === undefined && c.upper === undefined) return null
  const lower = c.lower ?? 0
  const upper = c.upper ?? 0
  if (lower > upper) return `lower (${lower}) must not be above upper (${upper})`
  return { lower, upper }
}

/** A unit axis from (dx, dy), or a refusal when it is (nearly) zero. */
function axisOf(dx: number, dy: number): Vec2 | string {
  const n = Math.sqrt(dx * dx + dy * dy)
  if (!(n >= 1e-6)) return `axis (dx, dy) = (${dx}, ${dy}) must not be zero`
  return { x: dx / n, y: dy / n }
}

/** A definition's joint, or its refusal: createJoint returns the id (accepted) or a reason. */
const refusalOf = (result: number | string): string | null => (typeof result === 'string' ? result : null)

/** The sandbox's joint commands (see the file comment). */
export const jointCommands: Record<string, GameCommandDefinition<undefined>> = {
  weld: {
    args: args({ ...bodies, x: coordinate, y: coordinate, ...spring, ...breaking }, ['a', 'b', 'x', 'y']),
    apply(ctx, player, c: WeldArgs) {
      const hz = c.hz ?? 0
      const damping = c.damping ?? 1
      const def: WireJointDef = {
        type: 'weld',
        ...common(c),
        anchor: clampToWorld(c.x, c.y),
        linearHertz: hz,
        angularHertz: hz,
        linearDampingRatio: damping,
        angularDampingRatio: damping,
      }
      return recordJoint(ctx, player, 'weld', ctx.createJoint(player, def, 'weld'))
    },
  },
  hinge: {
    args: args(
      {
        ...bodies,
        x: coordinate,
        y: coordinate,
        lower: angle,
        upper: angle,
        speed,
        torque: effort,
        ...breaking,
      },
      ['a', 'b', 'x', 'y'],
    ),
    apply(ctx, player, c: HingeArgs) {
      const limit = limits(c)
      if (typeof limit === 'string') return `hinge refused: ${limit}`
      const def: WireJointDef = {
        type: 'revolute',
        ...common(c),
        anchor: clampToWorld(c.x, c.y),
        enableLimit: limit !== null,
        lowerAngle: limit?.lower ?? 0,
        upperAngle: limit?.upper ?? 0,
        enableMotor: c.torque !== undefined,
        motorSpeed: c.speed ?? 0,
        maxMotorTorque: c.torque ?? 0,
      }
      return recordJoint(ctx, player, 'hinge', ctx.createJoint(player, def, 'hinge'))
    },
  },
  spring: {
    args: args(
      {
        ...bodies,
        ax: coordinate,
        ay: coordinate,
        bx: coordinate,
        by: coordinate,
        hz: { type: 'number', exclusiveMinimum: 0, maximum: MAX_JOINT_HERTZ },
        damping: spring.damping,
        length: { type: 'number', minimum: 0.001, maximum: MAX_ROPE_LENGTH },
        ...breaking,
      },
      ['a', 'b', 'ax', 'ay', 'bx', 'by', 'hz'],
    ),
    apply(ctx, player, c: SpringArgs) {
      const anchorA = clampToWorld(c.ax, c.ay)
      const anchorB = clampToWorld(c.bx, c.by)
      const dx = anchorB.x - anchorA.x
      const dy = anchorB.y - anchorA.y
      const span = Math.sqrt(dx * dx + dy * dy)
      if (span > MAX_ROPE_LENGTH) return `spring longer than ${MAX_ROPE_LENGTH} m`
      const def: WireJointDef = {
        type: 'distance',
        ...common(c),
        anchorA,
        anchorB,
        length: c.length ?? Math.max(span, 0.001),
        hertz: c.hz,
        dampingRatio: c.damping ?? 0.5,
      }
      return recordJoint(ctx, player, 'spring', ctx.createJoint(player, def, 'spring'))
    },
  },
  slider: {
    args: args(
      {
        ...bodies,
        x: coordinate,
        y: coordinate,
        dx: coordinate,
        dy: coordinate,
        lower: travel,
        upper: travel,
        speed,
        force: effort,
        ...spring,
        ...breaking,
      },
      ['a', 'b', 'x', 'y', 'dx', 'dy'],
    ),
    apply(ctx, player, c: SliderArgs) {
      const axis = axisOf(c.dx, c.dy)
      if (typeof axis === 'string') return `slider refused: ${axis}`
      const limit = limits(c)
      if (typeof limit === 'string') return `slider refused: ${limit}`
      const hz = c.hz ?? 0
      const def: WireJointDef = {
        type: 'prismatic',
        ...common(c),
        anchor: clampToWorld(c.x, c.y),
        axis,
        enableLimit: limit !== null,
        lower: limit?.lower ?? 0,
        upper: limit?.upper ?? 0,
        enableMotor: c.force !== undefined,
        motorSpeed: c.speed ?? 0,
        maxMotorForce: c.force ?? 0,
        enableSpring: hz > 0,
        hertz: hz,
        dampingRatio: c.damping ?? 0.7,
      }
      return recordJoint(ctx, player, 'slider', ctx.createJoint(player, def, 'slider'))
    },
  },
  wheel: {
    args: args(
      {
        a: bodies.a,
        b: bodies.b,
        radius: { type: 'number', minimum: 0.05, maximum: 10 },
        x: coordinate,
        y: coordinate,
        dx: coordinate,
        dy: coordinate,
        lower: travel,
        upper: travel,
        ...spring,
        speed,
        torque: effort,
        ...breaking,
      },
      ['a'],
    ),
    apply(ctx, player, c: WheelArgs) {
      // The wheel is an existing body (b) or one this command makes (radius, at x, y).
      if ((c.b === undefined) === (c.radius === undefined))
        return 'wheel refused: give b (the wheel body) or radius (a new wheel at x, y), not both'
      if (c.radius !== undefined && (c.x === undefined || c.y === undefined))
        return 'wheel refused: a new wheel (radius) needs x and y'
      const axis = axisOf(c.dx ?? 0, c.dy ?? 1)
      if (typeof axis === 'string') return `wheel refused: ${axis}`
      const limit = limits(c)
      if (typeof limit === 'string') return `wheel refused: ${limit}`
      let at: Vec2
      if (c.b !== undefined) {
        if (!ctx.world.hasBody(c.b)) return `body ${c.b} does not exist or is static`
        // The anchor is the wheel's centre unless given: the wheel spins about it.
        at =
          c.x === undefined && c.y === undefined ? ctx.world.getPosition(c.b) : { x: c.x ?? 0, y: c.y ?? 0 }
      } else at = { x: c.x ?? 0, y: c.y ?? 0 }
      const anchor = clampToWorld(at.x, at.y)
      let b = c.b ?? 0
      if (c.b === undefined) {
        // A new wheel: everything the joint needs is checked before the body is made, so a
        // refusal changes nothing (a joint refused after it would throw: applied everywhere alike).
        if (c.a !== 0 && !ctx.world.hasBody(c.a)) return `body ${c.a} does not exist`
        const far = c.a === 0 ? null : anchorRefusal(ctx.world, c.a, anchor, 'wheel anchor')
        if (far) return far
        const made = ctx.createBody({
          type: 'dynamic',
          position: anchor,
          shape: circle(c.radius ?? 0.5),
          density: 1,
          friction: 0.9,
        })
        if (typeof made === 'string') return made
        b = made
      }
      const hz = c.hz ?? 4
      const def: WireJointDef = {
        type: 'wheel',
        ...common({ ...c, b }),
        anchor,
        axis,
        enableSpring: hz > 0,
        hertz: hz,
        dampingRatio: c.damping ?? 0.7,
        enableLimit: limit !== null,
        lower: limit?.lower ?? 0,
        upper: limit?.upper ?? 0,
        enableMotor: c.torque !== undefined,
        motorSpeed: c.speed ?? 0,
        maxMotorTorque: c.torque ?? 0,
      }
      const joined = ctx.createJoint(player, def, 'wheel')
      if (typeof joined === 'string' && c.b === undefined) throw new Error(joined)
      // Undoable: the joint, and the wheel with it when this command made one.
      if (typeof joined === 'number' && c.b === undefined)
        recordAction(ctx, player, 'wheel', NO_ITEMS, captureBodies(ctx, [b]))
      else if (typeof joined === 'number') recordJoint(ctx, player, 'wheel', joined)
      return refusalOf(joined)
    },
  },
  jointMotor: {
    args: args({ joint: { type: 'integer', minimum: 1, maximum: Number.MAX_SAFE_INTEGER }, speed }, [
      'joint',
      'speed',
    ]),
    apply(ctx, player, c: { joint: number; speed: number }) {
      const j = ctx.userJoint(c.joint)
      if (!j) return `joint ${c.joint} is not a joint in this room`
      if (j.owner !== player)
        return j.owner === 0
          ? `joint ${c.joint} is the scene's: only its maker may drive its motor`
          : `joint ${c.joint} belongs to player ${j.owner}: only its maker may drive its motor`
      return ctx.setJointMotor(c.joint, c.speed)
    },
  },
  editJoint: {
    args: args(
      {
        joint: { type: 'integer', minimum: 1, maximum: Number.MAX_SAFE_INTEGER },
        limit: { type: 'boolean' },
        lower: travel,
        upper: travel,
        motor: { type: 'boolean' },
        speed,
        torque: { type: 'number', minimum: 0, maximum: MAX_JOINT_MOTOR_EFFORT },
        force: { type: 'number', minimum: 0, maximum: MAX_JOINT_MOTOR_EFFORT },
        spring: { type: 'boolean' },
        hz: spring.hz,
        damping: spring.damping,
        target: travel,
        ahz: spring.hz,
        adamping: spring.damping,
        length: { type: 'number', minimum: 0.001, maximum: MAX_ROPE_LENGTH },
        min: { type: 'number', minimum: 0, maximum: MAX_ROPE_LENGTH },
        max: { type: 'number', minimum: 0.001, maximum: MAX_ROPE_LENGTH },
        correction: { type: 'number', minimum: 0, maximum: 1 },
        breakForce: { type: 'number', minimum: 0, maximum: MAX_BREAK },
        breakTorque: { type: 'number', minimum: 0, maximum: MAX_BREAK },
      },
      ['joint'],
    ),
    apply(ctx, player, c: EditJointArgs) {
      const refusal = editJointRefusal(ctx, player, c.joint)
      if (refusal) return refusal
      const joint = ctx.userJoint(c.joint) as Readonly<WireJoint>
      const settings = editJointSettings(joint, c)
      if (typeof settings === 'string') return settings
      const before = captureJoints(ctx, [c.joint])
      const failed = ctx.setJointSettings(c.joint, settings)
      if (failed) return `editJoint refused: ${failed}`
      recordAction(ctx, player, 'editJoint', before, captureJoints(ctx, [c.joint]))
      return null
    },
  },
}
