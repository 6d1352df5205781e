/*
 * Scene files (docs/scene-format.md): a world as versioned JSON, to save a room, open it again
 * and share it. saveScene reads a world through the engine's public read-back (getBodyDef,
 * getShapeDef, getJointDef: exact frames and rotations), so a file opened and saved again is the
 * same file, byte for byte; parseScene checks a file's size, its JSON, its schema
 * (scene-schema.ts) and what the schema cannot say, naming the field of the first error
 * (`bodies[3].shapes[0].radius must be > 0`); buildScene makes the world, the same bits on every
 * machine (bodies in file order, then joints in file order), so a loaded scene is part of a room's
 * deterministic state.
 *
 * Not kept: contacts and their warm-starting impulses, joint impulses, sleep timers, body and joint
 * ids (bodies are numbered in file order), grabs (mouse joints), rolling resistance, tangent speed
 * and the event flags. A world opened from a file therefore starts like a freshly built scene, not
 * like the saved world's next step.
 */
import {
  box,
  type CompoundBodyDef,
  capsule,
  chain,
  circle,
  convexPolygon,
  cos,
  createWorld,
  type Filter,
  type JointDef,
  type JointFrames,
  type Shape,
  type ShapeDef,
  segment,
  sin,
  type Vec2,
  type World,
} from '../../engine/index.ts'
import {
  cssColor,
  type RoomSimulation,
  type WireJoint,
  type WireJointDef,
  wireJoint,
} from '../../shared/index.ts'
import { compileArgs } from '../args-schema.ts'
import { SCENE_FORMAT_VERSION, SCENE_LIMITS, SCENE_SCHEMA } from './scene-schema.ts'

/** A vector as the file holds it. */
export interface SceneVec {
  x: number
  y: number
}

/** A shape in a scene file (one kind's fields are given; see docs/scene-format.md). */
export interface SceneShape {
  type: 'circle' | 'box' | 'polygon' | 'capsule' | 'segment' | 'chainSegment'
  radius?: number
  center?: SceneVec
  halfWidth?: number
  halfHeight?: number
  vertices?: SceneVec[]
  center1?: SceneVec
  center2?: SceneVec
  point1?: SceneVec
  point2?: SceneVec
  ghost1?: SceneVec
  ghost2?: SceneVec
  density?: number
  friction?: number
  restitution?: number
  /** Rolling resistance (0-100, default 0). */
  rollingResistance?: number
  /** Surface speed (m/s, -1000-1000, default 0). */
  tangentSpeed?: number
  filter?: Filter
  sensor?: boolean
}

/** A body in a scene file. */
export interface SceneBody {
  type: 'static' | 'kinematic' | 'dynamic'
  position: SceneVec
  angle?: number
  rotation?: { c: number; s: number }
  linearVelocity?: SceneVec
  angularVelocity?: number
  linearDamping?: number
  angularDamping?: number
  gravityScale?: number
  bullet?: boolean
  fixedRotation?: boolean
  enableSleep?: boolean
  awake?: boolean
  color?: string
  shapes: SceneShape[]
}

/** A joint in a scene file: bodies are indices into `bodies` (null: the world frame). */
export interface SceneJoint {
  type: 'revolute' | 'distance' | 'weld' | 'prismatic' | 'wheel' | 'motor'
  bodyA: number | null
  bodyB: number
  [setting: string]: unknown
}

/** A scene file's content. */
export interface SceneFile {
  format: 'concord-scene'
  version: number
  name?: string
  gravity: SceneVec
  bodies: SceneBody[]
  joints?: SceneJoint[]
}

/** A scene built into a world: body ids in file order, and each body's colour where the file gives one. */
export interface BuiltScene {
  world: World
  bodies: number[]
  colors: Map<number, string>
}

/** Options of saveScene. */
export interface SaveSceneOptions {
  /** The scene's name (1-64 characters). */
  name?: string
  /** A body's colour (#rrggbb), if the caller keeps colours. */
  colorOf?: (body: number) => string | undefined
}

const checkSchema = compileArgs('scene', SCENE_SCHEMA)

/** The world as a scene file (see the file comment for what is not kept). */
export function saveScene(world: World, options: SaveSceneOptions = {}): SceneFile {
  const ids = world.bodyIds()
  const index = new Map<number, number>()
  ids.forEach((id, i) => {
    index.set(id, i)
  })
  const g = world.getGravity()
  const scene: SceneFile = {
    format: 'concord-scene',
    version: SCENE_FORMAT_VERSION,
    ...(options.name === undefined ? {} : { name: options.name }),
    gravity: { x: g.x, y: g.y },
    bodies: ids.map((id) => saveSceneBody(world, id, options.colorOf?.(id))),
    joints: [],
  }
  for (const id of world.jointIds()) {
    const joint = saveSceneJoint(world.getJointDef(id), index)
    if (joint) scene.joints?.push(joint)
  }
  return scene
}

/** A scene file's text: JSON, one body or joint per line, ending in a newline. */
export function sceneText(scene: SceneFile): string {
  const head = { ...scene, bodies: undefined, joints: undefined }
  const lines = JSON.stringify(head).slice(0, -1)
  const list = (items: readonly unknown[]) =>
    items.length === 0 ? '[]' : `[\n${items.map((item) => JSON.stringify(item)).join(',\n')}\n]`
  return `${lines},"bodies":${list(scene.bodies)},"joints":${list(scene.joints ?? [])}}\n`
}

/** One body as a scene file holds it (`color`: its #rrggbb, if kept); saveScene writes each body so. */
export function saveSceneBody(world: World, id: number, color: string | undefined): SceneBody {
  const def = world.getBodyDef(id)
  const type = def.type ?? 'dynamic'
  const p = def.position ?? { x: 0, y: 0 }
  const body: SceneBody = { type, position: { x: p.x, y: p.y }, angle: def.angle ?? 0, shapes: [] }
  if (def.rotation) body.rotation = { c: def.rotation.c, s: def.rotation.s }
  if (type !== 'static') {
    const v = def.linearVelocity ?? { x: 0, y: 0 }
    body.linearVelocity = { x: v.x, y: v.y }
    body.angularVelocity = def.angularVelocity ?? 0
  }
  if (def.linearDamping) body.linearDamping = def.linearDamping
  if (def.angularDamping) body.angularDamping = def.angularDamping
  if (def.gravityScale !== undefined && def.gravityScale !== 1) body.gravityScale = def.gravityScale
  if (def.bullet) body.bullet = true
  if (def.fixedRotation) body.fixedRotation = true
  if (def.enableSleep === false) body.enableSleep = false
  if (type !== 'static' && def.awake === false) body.awake = false
  if (color !== undefined) body.color = color
  body.shapes = def.shapes.map(saveShape)
  return body
}

const vec = (v: Vec2): SceneVec => ({ x: v.x, y: v.y })

function saveShape(def: ShapeDef): SceneShape {
  const s = def.shape
  let out: SceneShape
  if (s.type === 'circle') {
    out = { type: 'circle', radius: s.radius }
    if (s.centroid.x !== 0 || s.centroid.y !== 0) out.center = vec(s.centroid)
  } else if (s.type === 'capsule') {
    out = { type: 'capsule', center1: vec(s.vertices[0]), center2: vec(s.vertices[1]), radius: s.radius }
  } else if (s.type === 'segment') {
    out = { type: 'segment', point1: vec(s.vertices[0]), point2: vec(s.vertices[1]) }
  } else if (s.type === 'chainSegment') {
    // One segment of a chain, with the ghost points that smooth its joins: rebuilt exactly as the
    // one segment of a four-point open chain.
    out = {
      type: 'chainSegment',
      ghost1: vec(s.ghost1),
      point1: vec(s.vertices[0]),
      point2: vec(s.vertices[1]),
      ghost2: vec(s.ghost2),
    }
  } else if (s.type === 'chain') {
    throw new RangeError('a chain is saved as its segments (world.getShapeDef gives one per segment)')
  } else if (s.box) {
    out = { type: 'box', halfWidth: s.box.halfWidth, halfHeight: s.box.halfHeight }
  } else {
    out = { type: 'polygon', vertices: s.vertices.map(vec) }
    if (s.radius > 0) out.radius = s.radius
  }
  out.density = def.density ?? 1
  out.friction = def.friction ?? 0.6
  out.restitution = def.restitution ?? 0
  // Written only when set, so a world without them saves the same file as before they existed.
  if (def.rollingResistance) out.rollingResistance = def.rollingResistance
  if (def.tangentSpeed) out.tangentSpeed = def.tangentSpeed
  const f = def.filter
  if (f && (f.categoryBits !== 1 || f.maskBits !== 0xffffffff || f.groupIndex !== 0))
    out.filter = { categoryBits: f.categoryBits, maskBits: f.maskBits, groupIndex: f.groupIndex }
  if (def.sensor) out.sensor = true
  return out
}

/** Settings each joint kind saves, in this order (besides the bodies, frames and breaking). */
const JOINT_SETTINGS: Record<SceneJoint['type'], readonly string[]> = {
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
  ],
  weld: ['linearHertz', 'angularHertz', 'linearDampingRatio', 'angularDampingRatio'],
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
  ],
  wheel: [
    'enableSpring',
    'hertz',
    'dampingRatio',
    'enableLimit',
    'lower',
    'upper',
    'enableMotor',
    'motorSpeed',
    'maxMotorTorque',
  ],
  motor: ['linearOffset', 'angularOffset', 'maxForce', 'maxTorque', 'correctionFactor'],
}

/**
 * One joint as a scene file holds it, its bodies numbered by `index` (body id -> the number the
 * joint names it by: the file's body index); null for a mouse joint (a grab).
 */
export function saveSceneJoint(def: JointDef, index: Map<number, number>): SceneJoint | null {
  if (def.type === 'mouse') return null // grabs belong to players, not to the scene
  const bodyA = def.bodyA === null ? null : (index.get(def.bodyA) as number)
  const out: SceneJoint = { type: def.type, bodyA, bodyB: index.get(def.bodyB) as number }
  const settings = def as unknown as Record<string, unknown>
  if (def.type !== 'motor' && def.frames) {
    out.localAnchorA = vec(def.frames.localAnchorA)
    out.localAnchorB = vec(def.frames.localAnchorB)
    if (def.type !== 'distance') out.referenceAngle = def.frames.referenceAngle
    if (def.frames.localAxisA) out.localAxisA = vec(def.frames.localAxisA)
  }
  out.collideConnected = def.collideConnected === true
  for (const key of JOINT_SETTINGS[def.type]) {
    const value = settings[key]
    out[key] = typeof value === 'object' && value !== null ? vec(value as Vec2) : value
  }
  if (def.breakForce !== undefined) out.breakForce = def.breakForce
  if (def.breakTorque !== undefined) out.breakTorque = def.breakTorque
  return out
}

/** The outcome of parseScene: the scene, or the first error, naming the field. */
export type ParsedScene = { ok: true; scene: SceneFile } | { ok: false; error: string }

/** UTF-8 length of a string, without allocating its bytes. */
function utf8Length(text: string): number {
  let n = 0
  for (let i = 0; i < text.length; i++) {
    const c = text.charCodeAt(i)
    if (c < 0x80) n += 1
    else if (c < 0x800) n += 2
    else if (c >= 0xd800 && c <= 0xdbff) {
      n += 4
      i++
    } else n += 3
  }
  return n
}

/**
 * Parse and check a scene file's text: its size, its JSON, its version, its schema and the rules
 * the schema cannot state (checkScene). Building can still refuse a scene (buildScene).
 */
export function parseScene(text: string): ParsedScene {
  if (typeof text !== 'string') return { ok: false, error: 'a scene file must be text' }
  const bytes = utf8Length(text)
  if (bytes > SCENE_LIMITS.bytes)
    return { ok: false, error: `the scene file is ${bytes} bytes; the limit is ${SCENE_LIMITS.bytes}` }
  let value: unknown
  try {
    value = JSON.parse(text)
  } catch (e) {
    return { ok: false, error: `the scene file is not JSON: ${(e as Error).message}` }
  }
  return checkScene(value)
}

/** Check a decoded scene file (schema and semantic rules); the first error names the field. */
export function checkScene(value: unknown): ParsedScene {
  if (typeof value !== 'object' || value === null || Array.isArray(value))
    return { ok: false, error: 'a scene file must be a JSON object' }
  const v = value as Record<string, unknown>
  if (v.format !== 'concord-scene') return { ok: false, error: 'format must be "concord-scene"' }
  if (v.version !== SCENE_FORMAT_VERSION)
    return {
      ok: false,
      error: `version ${JSON.stringify(v.version)} is not supported: this build reads scene format version ${SCENE_FORMAT_VERSION}`,
    }
  const invalid = checkSchema(value)
  if (invalid !== null) return { ok: false, error: invalid }
  const scene = value as unknown as SceneFile
  const problem = semanticProblem(scene)
  return problem === null ? { ok: true, scene } : { ok: false, error: problem }
}

/** Fields each shape kind needs (the schema lists every kind's fields on one object). */
const SHAPE_FIELDS: Record<SceneShape['type'], readonly (keyof SceneShape)[]> = {
  circle: ['radius'],
  box: ['halfWidth', 'halfHeight'],
  polygon: ['vertices'],
  capsule: ['center1', 'center2', 'radius'],
  segment: ['point1', 'point2'],
  chainSegment: ['ghost1', 'point1', 'point2', 'ghost2'],
}
const GEOMETRY_FIELDS = [
  'radius',
  'center',
  'halfWidth',
  'halfHeight',
  'vertices',
  'center1',
  'center2',
  'point1',
  'point2',
  'ghost1',
  'ghost2',
] as const
const SHAPE_OPTIONAL: Record<SceneShape['type'], readonly string[]> = {
  circle: ['center'],
  box: [],
  polygon: ['radius'],
  capsule: [],
  segment: [],
  chainSegment: [],
}

function semanticProblem(scene: SceneFile): string | null {
  let shapes = 0
  for (let i = 0; i < scene.bodies.length; i++) {
    const body = scene.bodies[i]
    shapes += body.shapes.length
    if (shapes > SCENE_LIMITS.shapes) return `bodies holds more than ${SCENE_LIMITS.shapes} shapes in all`
    for (let k = 0; k < body.shapes.length; k++) {
      const shape = body.shapes[k]
      const at = `bodies[${i}].shapes[${k}]`
      for (const field of SHAPE_FIELDS[shape.type])
        if (shape[field] === undefined) return `${at}.${field} is required for a ${shape.type}`
      for (const field of GEOMETRY_FIELDS)
        if (
          shape[field] !== undefined &&
          !SHAPE_FIELDS[shape.type].includes(field) &&
          !SHAPE_OPTIONAL[shape.type].includes(field)
        )
          return `${at}.${field} is not a field of a ${shape.type}`
      if ((shape.type === 'circle' || shape.type === 'capsule') && !((shape.radius as number) > 0))
        return `${at}.radius must be > 0`
    }
  }
  const joints = scene.joints ?? []
  for (let j = 0; j < joints.length; j++) {
    const joint = joints[j]
    const at = `joints[${j}]`
    for (const side of ['bodyA', 'bodyB'] as const) {
      const index = joint[side]
      if (index !== null && index >= scene.bodies.length)
        return `${at}.${side} must be < ${scene.bodies.length} (the number of bodies)`
    }
    if (joint.bodyA === joint.bodyB) return `${at}.bodyB must differ from bodyA`
    const problem = jointFieldProblem(joint, at)
    if (problem) return problem
  }
  return null
}

const FRAME_FIELDS = ['localAnchorA', 'localAnchorB', 'referenceAngle', 'localAxisA']
const WORLD_FIELDS = ['anchor', 'anchorA', 'anchorB', 'axis']

/** Which of a joint's fields belong to its kind, and whether its anchors are given one complete way. */
function jointFieldProblem(joint: SceneJoint, at: string): string | null {
  const kind = joint.type
  const slider = kind === 'prismatic' || kind === 'wheel'
  const allowed = new Set(['type', 'bodyA', 'bodyB', 'collideConnected', 'breakForce', 'breakTorque'])
  for (const key of JOINT_SETTINGS[kind]) allowed.add(key)
  if (kind !== 'motor') {
    allowed.add('localAnchorA').add('localAnchorB')
    if (kind !== 'distance') allowed.add('referenceAngle')
    if (slider) allowed.add('localAxisA').add('axis')
    if (kind === 'distance') allowed.add('anchorA').add('anchorB')
    else allowed.add('anchor')
  }
  for (const key of Object.keys(joint))
    if (!allowed.has(key)) return `${at}.${key} is not a field of a ${kind} joint`
  if (kind === 'motor') return null
  const local = FRAME_FIELDS.some((f) => joint[f] !== undefined)
  const world = WORLD_FIELDS.some((f) => joint[f] !== undefined)
  if (local && world) return `${at} gives both local frames and world anchors; give one`
  const need = local
    ? [
        'localAnchorA',
        'localAnchorB',
        ...(kind === 'distance' ? [] : ['referenceAngle']),
        ...(slider ? ['localAxisA'] : []),
      ]
    : [...(kind === 'distance' ? ['anchorA', 'anchorB'] : ['anchor']), ...(slider ? ['axis'] : [])]
  for (const field of need) if (joint[field] === undefined) return `${at}.${field} is required`
  return null
}

/** A scene shape as an engine shape definition (geometry checked by the engine). */
function shapeDef(s: SceneShape): ShapeDef {
  let shape: Shape
  if (s.type === 'circle') shape = circle(s.radius as number, s.center)
  else if (s.type === 'box') shape = box(s.halfWidth as number, s.halfHeight as number)
  else if (s.type === 'polygon') shape = convexPolygon(s.vertices as SceneVec[], s.radius ?? 0)
  else if (s.type === 'capsule')
    shape = capsule(s.center1 as SceneVec, s.center2 as SceneVec, s.radius as number)
  else if (s.type === 'segment') shape = segment(s.point1 as SceneVec, s.point2 as SceneVec)
  else {
    const points = [s.ghost1, s.point1, s.point2, s.ghost2] as SceneVec[]
    const def: ShapeDef = { shape: chain(points) }
    if (s.density !== undefined) def.density = s.density
    if (s.friction !== undefined) def.friction = s.friction
    if (s.restitution !== undefined) def.restitution = s.restitution
    if (s.rollingResistance !== undefined) def.rollingResistance = s.rollingResistance
    if (s.tangentSpeed !== undefined) def.tangentSpeed = s.tangentSpeed
    if (s.filter !== undefined) def.filter = s.filter
    return def
  }
  const def: ShapeDef = { shape }
  if (s.density !== undefined) def.density = s.density
  if (s.friction !== undefined) def.friction = s.friction
  if (s.restitution !== undefined) def.restitution = s.restitution
  if (s.rollingResistance !== undefined) def.rollingResistance = s.rollingResistance
  if (s.tangentSpeed !== undefined) def.tangentSpeed = s.tangentSpeed
  if (s.filter !== undefined) def.filter = s.filter
  if (s.sensor !== undefined) def.sensor = s.sensor
  return def
}

/**
 * Build a checked scene (parseScene or checkScene) into a fresh world: bodies in file order, then
 * joints in file order. Returns the world, or the first error naming the body or joint the engine
 * refused (`bodies[2].shapes[0]: polygon must be convex ...`). The same file builds the same bits
 * everywhere.
 */
export function buildScene(scene: SceneFile): { ok: true; built: BuiltScene } | { ok: false; error: string } {
  const world = createWorld()
  world.setGravity(scene.gravity)
  const ids: number[] = []
  const colors = new Map<number, string>()
  for (let i = 0; i < scene.bodies.length; i++) {
    const b = scene.bodies[i]
    const shapes: ShapeDef[] = []
    for (let k = 0; k < b.shapes.length; k++) {
      try {
        shapes.push(shapeDef(b.shapes[k]))
      } catch (e) {
        return { ok: false, error: `bodies[${i}].shapes[${k}]: ${(e as Error).message}` }
      }
    }
    if (b.rotation && b.angle !== undefined) {
      const c = cos(b.angle)
      const s = sin(b.angle)
      // Only a consistency check of the file (the angle itself is not used): not simulation state.
      if (Math.abs(c - b.rotation.c) > 1e-6 || Math.abs(s - b.rotation.s) > 1e-6)
        return {
          ok: false,
          error: `bodies[${i}].angle disagrees with bodies[${i}].rotation (remove rotation to use angle)`,
        }
    }
    try {
      const id = world.createBody(bodyDef(b, shapes))
      ids.push(id)
      if (b.color !== undefined) colors.set(id, b.color.toLowerCase())
    } catch (e) {
      return { ok: false, error: `bodies[${i}]: ${(e as Error).message}` }
    }
  }
  const joints = scene.joints ?? []
  for (let j = 0; j < joints.length; j++) {
    try {
      world.createJoint(sceneJointDef(world, joints[j], (i) => ids[i]))
    } catch (e) {
      return { ok: false, error: `joints[${j}]: ${(e as Error).message}` }
    }
  }
  // Creating a joint wakes its bodies: put back to sleep what the file saved asleep.
  for (let i = 0; i < scene.bodies.length; i++)
    if (scene.bodies[i].awake === false && world.isAwake(ids[i])) world.setAwake(ids[i], false)
  return { ok: true, built: { world, bodies: ids, colors } }
}

/** A room's world as a scene file named `name`, with the colours the room keeps for its bodies. */
export function saveRoomScene(sim: RoomSimulation, name: string): SceneFile {
  return saveScene(sim.world, { name, colorOf: (body) => cssColor(sim.bodyColors.get(body)) ?? undefined })
}

/**
 * A checked scene built for a room to open (RoomSimulation.loadWorld): the world, its joints as
 * they travel (a file holds no mouse joints: a grab is a player's, not a scene's) and its bodies'
 * colours as a room keeps them (flat [body id, 0xRRGGBB, ...], ascending ids); or buildScene's
 * first error. The server's openScene and the offline page's Open both build a file here.
 */
export function sceneForRoom(
  scene: SceneFile,
): { ok: true; world: World; joints: WireJoint[]; colors: number[] } | { ok: false; error: string } {
  const built = buildScene(scene)
  if (!built.ok) return built
  const world = built.built.world
  const joints: WireJoint[] = []
  for (const id of world.jointIds()) {
    const def = world.getJointDef(id)
    if (def.type !== 'mouse') joints.push(wireJoint(world, id, def as WireJointDef))
  }
  const colors: number[] = []
  for (const id of [...built.built.colors.keys()].sort((a, b) => a - b))
    colors.push(id, Number.parseInt((built.built.colors.get(id) as string).slice(1), 16))
  return { ok: true, world, joints, colors }
}

/** A scene body's engine definition, with its shapes' definitions already made. */
function bodyDef(b: SceneBody, shapes: ShapeDef[]): CompoundBodyDef {
  return {
    type: b.type,
    position: b.position,
    angle: b.angle ?? 0,
    rotation: b.rotation,
    linearVelocity: b.linearVelocity,
    angularVelocity: b.angularVelocity,
    linearDamping: b.linearDamping,
    angularDamping: b.angularDamping,
    gravityScale: b.gravityScale,
    bullet: b.bullet,
    fixedRotation: b.fixedRotation,
    enableSleep: b.enableSleep,
    awake: b.awake,
    shapes,
  }
}

/**
 * One scene body (saveSceneBody's) as an engine definition, as buildScene makes it (its angle is
 * not checked against its rotation: the rotation wins); throws on a shape the engine refuses.
 */
export function sceneBodyDef(b: SceneBody): CompoundBodyDef {
  return bodyDef(b, b.shapes.map(shapeDef))
}

/**
 * A scene joint (saveSceneJoint's) as an engine definition in `world`, its bodies resolved by
 * `bodyOf` (the joint's number for a body -> the body's id in `world`: buildScene's built ids).
 */
export function sceneJointDef(world: World, joint: SceneJoint, bodyOf: (index: number) => number): JointDef {
  const bodyA = joint.bodyA === null ? null : bodyOf(joint.bodyA)
  const bodyB = bodyOf(joint.bodyB)
  const settings: Record<string, unknown> = {}
  for (const key of JOINT_SETTINGS[joint.type]) if (joint[key] !== undefined) settings[key] = joint[key]
  for (const key of ['collideConnected', 'breakForce', 'breakTorque'])
    if (joint[key] !== undefined) settings[key] = joint[key]
  if (joint.type === 'motor') return { type: 'motor', bodyA, bodyB, ...settings } as JointDef
  const toWorld = (body: number | null, p: SceneVec): Vec2 =>
    body === null ? { x: p.x, y: p.y } : world.getWorldPoint(body, p)
  let frames: JointFrames | undefined
  let anchorA: Vec2
  let anchorB: Vec2
  let axis = joint.axis as Vec2 | undefined
  if (joint.localAnchorA !== undefined) {
    frames = {
      localAnchorA: joint.localAnchorA as Vec2,
      localAnchorB: joint.localAnchorB as Vec2,
      referenceAngle: (joint.referenceAngle as number | undefined) ?? 0,
    }
    if (joint.localAxisA !== undefined) {
      frames.localAxisA = joint.localAxisA as Vec2
      // The world axis the definition needs; the exact local axis in `frames` wins.
      const a = frames.localAxisA
      if (bodyA === null) axis = { x: a.x, y: a.y }
      else {
        const r = world.getRotation(bodyA)
        axis = { x: r.c * a.x - r.s * a.y, y: r.s * a.x + r.c * a.y }
      }
    }
    anchorA = toWorld(bodyA, frames.localAnchorA)
    anchorB = toWorld(bodyB, frames.localAnchorB)
  } else {
    anchorA = (joint.type === 'distance' ? joint.anchorA : joint.anchor) as Vec2
    anchorB = (joint.type === 'distance' ? joint.anchorB : joint.anchor) as Vec2
  }
  const base = { bodyA, bodyB, ...(frames ? { frames } : {}), ...settings }
  if (joint.type === 'distance') return { type: 'distance', anchorA, anchorB, ...base } as JointDef
  if (joint.type === 'prismatic' || joint.type === 'wheel')
    return { type: joint.type, anchor: anchorB, axis, ...base } as JointDef
  return { type: joint.type, anchor: anchorB, ...base } as JointDef
}
