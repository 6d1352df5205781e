/*
 * The scene file's JSON Schema (draft 2020-12), written as data here and published as
 * docs/scene-format.schema.json (a test keeps the two equal). It uses only the keywords the game
 * argument checker allows (games/args-schema.ts: no $ref, no if/then), so one checker,
 * @cfworker/json-schema, validates a scene on the server and in a page under a CSP that forbids
 * eval. What a schema without if/then cannot say (which fields each shape and joint kind needs,
 * joint body indices in range, convex polygons, a dynamic body with mass) is checked by
 * scene-file.ts, with errors that name the field the same way.
 */
import type { ArgsSchema } from '../args-schema.ts'

/** The scene format's version: a file of another version is refused, naming both. */
export const SCENE_FORMAT_VERSION = 1

/** Limits of a scene file: bytes of its text, bodies, shapes in all, joints. */
export const SCENE_LIMITS = { bytes: 4 * 1024 * 1024, bodies: 5000, shapes: 20000, joints: 5000 } as const

const number = { type: 'number' } as const
const positive = { type: 'number', exclusiveMinimum: 0 } as const
const nonNegative = { type: 'number', minimum: 0 } as const
const boolean = { type: 'boolean' } as const

/** A closed object schema: these properties, `required` of them, nothing else. */
function object(properties: Record<string, object>, required: string[] = []): ArgsSchema {
  return { type: 'object', properties, required, additionalProperties: false }
}

const vec = object({ x: number, y: number }, ['x', 'y'])
const unitRange = { type: 'number', minimum: 0, maximum: 1 } as const
const bodyIndex = { type: 'integer', minimum: 0, maximum: SCENE_LIMITS.bodies - 1 } as const

const shape = object(
  {
    type: {
      description: 'the shape kind (chainSegment: one segment of a one-sided chain, static bodies only)',
      enum: ['circle', 'box', 'polygon', 'capsule', 'segment', 'chainSegment'],
    },
    radius: { description: 'circle, capsule (> 0); polygon rounding (>= 0)', ...nonNegative },
    center: { description: 'circle: its centre in the body frame (m), default the origin', ...vec },
    halfWidth: { description: 'box (centred on the body origin, not turned)', ...positive },
    halfHeight: { description: 'box', ...positive },
    vertices: {
      description: 'polygon: 3 to 8 points in the body frame, convex',
      type: 'array',
      items: vec,
      minItems: 3,
      maxItems: 8,
    },
    center1: { description: 'capsule: the first centre', ...vec },
    center2: { description: 'capsule: the second centre', ...vec },
    point1: { description: 'segment, chainSegment: the first end', ...vec },
    point2: { description: 'segment, chainSegment: the second end', ...vec },
    ghost1: { description: "chainSegment: the chain's point before point1", ...vec },
    ghost2: { description: "chainSegment: the chain's point after point2", ...vec },
    density: { description: 'kg/m^2, default 1', type: 'number', minimum: 1e-6, maximum: 1e6 },
    friction: { description: 'default 0.6', type: 'number', minimum: 0, maximum: 100 },
    restitution: { description: 'default 0', ...unitRange },
    rollingResistance: {
      description: 'rolling resistance coefficient (engine/README.md); default 0',
      type: 'number',
      minimum: 0,
      maximum: 100,
    },
    tangentSpeed: {
      description: 'surface speed along the outline (m/s), a conveyor belt; default 0',
      type: 'number',
      minimum: -1000,
      maximum: 1000,
    },
    filter: object(
      {
        categoryBits: { type: 'integer', minimum: 0, maximum: 4294967295 },
        maskBits: { type: 'integer', minimum: 0, maximum: 4294967295 },
        groupIndex: { type: 'integer', minimum: -2147483648, maximum: 2147483647 },
      },
      ['categoryBits', 'maskBits', 'groupIndex'],
    ),
    sensor: { description: 'detects overlap, never pushes; default false', ...boolean },
  },
  ['type'],
)

const body = object(
  {
    type: { enum: ['static', 'kinematic', 'dynamic'] },
    position: { description: 'the body origin (m)', ...vec },
    angle: {
      description: 'rad; ignored when rotation is given',
      type: 'number',
      minimum: -1e6,
      maximum: 1e6,
    },
    rotation: {
      description: 'the exact (cos, sin) of the angle, as saved; wins over angle',
      ...object({ c: number, s: number }, ['c', 's']),
    },
    linearVelocity: { description: 'of the centre of mass (m/s)', ...vec },
    angularVelocity: { description: 'rad/s', ...number },
    linearDamping: { type: 'number', minimum: 0, maximum: 1e6 },
    angularDamping: { type: 'number', minimum: 0, maximum: 1e6 },
    gravityScale: { type: 'number', minimum: -1000, maximum: 1000 },
    bullet: boolean,
    fixedRotation: boolean,
    enableSleep: boolean,
    awake: boolean,
    color: { description: '#rrggbb', type: 'string', pattern: '^#[0-9a-fA-F]{6}$' },
    shapes: { type: 'array', items: shape, minItems: 1, maxItems: 1024 },
  },
  ['type', 'position', 'shapes'],
)

const joint = object(
  {
    type: { enum: ['revolute', 'distance', 'weld', 'prismatic', 'wheel', 'motor'] },
    bodyA: {
      description: 'index into bodies, or null for the fixed world frame',
      anyOf: [bodyIndex, { type: 'null' }],
    },
    bodyB: { description: 'index into bodies', ...bodyIndex },
    localAnchorA: { description: "anchor in A's frame (m); with localAnchorB and referenceAngle", ...vec },
    localAnchorB: { description: "anchor in B's frame (m)", ...vec },
    referenceAngle: {
      description: 'angleB - angleA at creation (rad)',
      type: 'number',
      minimum: -4,
      maximum: 4,
    },
    localAxisA: { description: "prismatic, wheel: the axis in A's frame (unit)", ...vec },
    anchor: {
      description: 'revolute, weld, prismatic, wheel: a world anchor instead of the local ones',
      ...vec,
    },
    anchorA: { description: 'distance: world anchor on A instead of the local ones', ...vec },
    anchorB: { description: 'distance: world anchor on B', ...vec },
    axis: { description: 'prismatic, wheel: a world axis instead of localAxisA', ...vec },
    collideConnected: boolean,
    breakForce: { description: 'N; absent: never breaks', ...nonNegative },
    breakTorque: { description: 'N m; absent: never breaks', ...nonNegative },
    enableLimit: boolean,
    lowerAngle: { type: 'number', minimum: -Math.PI, maximum: Math.PI },
    upperAngle: { type: 'number', minimum: -Math.PI, maximum: Math.PI },
    lower: { description: 'prismatic, wheel: m', ...number },
    upper: number,
    enableMotor: boolean,
    motorSpeed: number,
    maxMotorTorque: nonNegative,
    maxMotorForce: nonNegative,
    enableSpring: boolean,
    hertz: nonNegative,
    dampingRatio: nonNegative,
    targetAngle: { type: 'number', minimum: -Math.PI, maximum: Math.PI },
    targetTranslation: number,
    length: positive,
    minLength: nonNegative,
    maxLength: positive,
    linearHertz: nonNegative,
    angularHertz: nonNegative,
    linearDampingRatio: nonNegative,
    angularDampingRatio: nonNegative,
    linearOffset: { description: "motor: B's centre in A's frame (m)", ...vec },
    angularOffset: { type: 'number', minimum: -1e6, maximum: 1e6 },
    maxForce: nonNegative,
    maxTorque: nonNegative,
    correctionFactor: unitRange,
  },
  ['type', 'bodyA', 'bodyB'],
)

/** The scene file's schema (docs/scene-format.md describes every field). */
export const SCENE_SCHEMA: ArgsSchema = {
  $schema: 'https://json-schema.org/draft/2020-12/schema',
  title: 'Concord scene file',
  description: 'A world to open in a Concord room: docs/scene-format.md',
  ...object(
    {
      format: { const: 'concord-scene' },
      version: { type: 'integer', minimum: 1 },
      name: { type: 'string', minLength: 1, maxLength: 64 },
      gravity: { description: 'm/s^2', ...vec },
      bodies: { type: 'array', items: body, maxItems: SCENE_LIMITS.bodies },
      joints: { type: 'array', items: joint, maxItems: SCENE_LIMITS.joints },
    },
    ['format', 'version', 'gravity', 'bodies'],
  ),
}
