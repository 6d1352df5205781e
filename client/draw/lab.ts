/*
 * The lab: a free-body diagram of one selected body with every force acting on it: gravity m g;
 * each contact's normal and friction force (the contact impulses of the last step divided by the
 * step: Box2D reports impulses, and an impulse over 1/60 s is an average force); and each joint's
 * and grab's reaction force (the engine's joint reaction: pins, rods, ropes, springs, and every
 * player's mouse joint). A contact's impulses act on body B along +normal and +tangent (tangent =
 * (ny, -nx)) and on body A with the opposite sign, exactly as the solver applies them; a joint's
 * reaction acts on body B and its opposite on body A. So a body at rest, however it is held (a
 * cradle ball hanging from its rod, a plank resting on the ground), shows a net force near zero.
 * With it: the body's velocity and kinetic energy (1/2 m v^2 + 1/2 I w^2).
 *
 * Offline the contacts come from the world stepping in the page; online from the room's server,
 * which streams the contacts of the body this player inspects after each snapshot (a `contacts`
 * message: the same impulses, read from the server's own world).
 *
 * On a box resting on a ramp of angle theta this gives normal = m g cos(theta) and friction =
 * m g sin(theta), and the net force is about zero: the browser test checks those numbers.
 */
import { type ContactInfo, STEP_SECONDS, type Vec2, type World } from '../../engine/index.ts'
import {
  type ContactsMessage,
  jointForceOn,
  type WireJointForceKind,
  type WireJointKind,
} from '../../shared/index.ts'
import type { LabContact, LabData, LabJointForce } from '../modes/index.ts'

/** One contact's forces on the selected body (N), applied at the mean contact point (m). */
export interface ContactForce {
  other: number
  point: Vec2
  normal: Vec2
  friction: Vec2
  /** Magnitudes (N). */
  normalN: number
  frictionN: number
}

/** One joint's or grab's force on the selected body (N), applied at its anchor (m). */
export interface JointForce {
  id: number
  kind: WireJointForceKind
  point: Vec2
  force: Vec2
  /** Magnitude (N). */
  size: number
}

/** The free-body diagram of one body. */
export interface FreeBody {
  mass: number
  gravity: Vec2
  contacts: ContactForce[]
  joints: JointForce[]
  net: Vec2
  /** Velocity (m/s), angular velocity (rad/s), kinetic energy (J). */
  velocity: Vec2
  angularVelocity: number
  kinetic: number
  source: LabData['source']
}

/** Lab data from the server's `contacts` message for the inspected body. */
export function labFromServer(message: ContactsMessage, gravity: Vec2): LabData {
  const contacts: LabContact[] = message.contacts.map((c) => ({
    bodyA: c.a,
    bodyB: c.b,
    normal: { x: c.nx, y: c.ny },
    points: c.points.map((p) => ({ point: { x: p.x, y: p.y }, normalImpulse: p.n, tangentImpulse: p.t })),
  }))
  const joints: LabJointForce[] = message.joints.map((j) => ({
    id: j.id,
    kind: j.kind,
    point: { x: j.x, y: j.y },
    force: { x: j.fx, y: j.fy },
  }))
  return {
    contacts,
    joints,
    mass: message.mass,
    inertia: message.inertia,
    velocity: { x: message.vx, y: message.vy },
    angularVelocity: message.w,
    gravity,
    source: 'server',
  }
}

/**
 * Lab data for `bodyId` read from a world stepping in the page: its contacts, every joint acting on
 * it (mouse joints are grabs; `kindOf` names the others' kinds), mass, inertia and velocity.
 */
export function labFromWorld(
  world: World,
  bodyId: number,
  contacts: readonly ContactInfo[],
  kindOf: (jointId: number) => WireJointKind | undefined,
): LabData {
  const joints: LabJointForce[] = []
  for (const info of world.joints()) {
    if (info.bodyA !== bodyId && info.bodyB !== bodyId) continue
    const kind = info.type === 'mouse' ? 'grab' : (kindOf(info.id) ?? 'pin')
    const f = jointForceOn(bodyId, info, kind)
    joints.push({ id: f.id, kind, point: { x: f.x, y: f.y }, force: { x: f.fx, y: f.fy } })
  }
  return {
    contacts,
    joints,
    mass: world.getMass(bodyId),
    inertia: world.getInertia(bodyId),
    velocity: world.getLinearVelocity(bodyId),
    angularVelocity: world.getAngularVelocity(bodyId),
    gravity: world.getGravity(),
    source: 'world',
  }
}

/** Forces on `bodyId` from the lab data (see the file comment for the sign conventions). */
export function computeFreeBody(bodyId: number, data: LabData): FreeBody {
  const gravity = { x: data.mass * data.gravity.x, y: data.mass * data.gravity.y }
  const net = { x: gravity.x, y: gravity.y }
  const contacts: ContactForce[] = []
  for (const c of data.contacts) {
    if (c.bodyA !== bodyId && c.bodyB !== bodyId) continue
    if (c.points.length === 0) continue
    const sign = c.bodyB === bodyId ? 1 : -1
    let n = 0
    let t = 0
    let px = 0
    let py = 0
    for (const p of c.points) {
      n += p.normalImpulse
      t += p.tangentImpulse
      px += p.point.x
      py += p.point.y
    }
    const fn = (sign * n) / STEP_SECONDS
    const ft = (sign * t) / STEP_SECONDS
    const normal = { x: fn * c.normal.x, y: fn * c.normal.y }
    const friction = { x: ft * c.normal.y, y: -ft * c.normal.x }
    net.x += normal.x + friction.x
    net.y += normal.y + friction.y
    contacts.push({
      other: c.bodyA === bodyId ? c.bodyB : c.bodyA,
      point: { x: px / c.points.length, y: py / c.points.length },
      normal,
      friction,
      normalN: Math.abs(fn),
      frictionN: Math.abs(ft),
    })
  }
  const joints: JointForce[] = data.joints.map((j) => {
    net.x += j.force.x
    net.y += j.force.y
    return { id: j.id, kind: j.kind, point: j.point, force: j.force, size: len(j.force) }
  })
  const v = data.velocity
  const w = data.angularVelocity
  const kinetic = 0.5 * data.mass * (v.x * v.x + v.y * v.y) + 0.5 * data.inertia * w * w
  return {
    mass: data.mass,
    gravity,
    contacts,
    joints,
    net,
    velocity: { x: v.x, y: v.y },
    angularVelocity: w,
    kinetic,
    source: data.source,
  }
}

/** A body's weight is drawn this long (m), or WEIGHT_MIN_PX on screen when that is longer. */
const WEIGHT_ARROW = 2
/** Shortest on-screen length of the weight arrow (CSS px): readable when the view is zoomed out. */
const WEIGHT_MIN_PX = 100
/** Longest arrow, in weights (3 weights: 6 m at the usual zoom). */
const MAX_WEIGHTS = 3

/**
 * How arrows are sized at a zoom of `scale` CSS px per metre: metres per newton (`unit`, so the
 * weight `weightN` is WEIGHT_ARROW m long, or WEIGHT_MIN_PX on screen if that is longer) and the
 * longest arrow (m).
 */
export function arrowScale(weightN: number, scale: number): { unit: number; max: number } {
  const weight = Math.max(WEIGHT_ARROW, WEIGHT_MIN_PX / Math.max(1e-6, scale))
  return { unit: weight / Math.max(1e-6, weightN), max: MAX_WEIGHTS * weight }
}
const fmt = (v: number): string => v.toFixed(2)
const len = (v: Vec2): number => Math.sqrt(v.x * v.x + v.y * v.y)

/** The lab panel's text, one line per force (values in newtons). */
export function describeFreeBody(bodyId: number, fb: FreeBody): string {
  const lines = [`body ${bodyId}   mass ${fmt(fb.mass)} kg`, `gravity  ${fmt(len(fb.gravity))} N`]
  for (const c of fb.contacts) {
    lines.push(`contact with ${c.other}: normal ${fmt(c.normalN)} N  friction ${fmt(c.frictionN)} N`)
  }
  if (fb.contacts.length === 0) lines.push('no contacts')
  for (const j of fb.joints) {
    lines.push(
      `${j.kind === 'grab' ? 'grab' : `${j.kind} ${j.id}`}: ${fmt(j.size)} N  (${fmt(j.force.x)}, ${fmt(j.force.y)})`,
    )
  }
  lines.push(`net force ${fmt(len(fb.net))} N  (${fmt(fb.net.x)}, ${fmt(fb.net.y)})`)
  lines.push(
    `velocity ${fmt(len(fb.velocity))} m/s  spin ${fmt(fb.angularVelocity)} rad/s  kinetic energy ${fmt(fb.kinetic)} J`,
  )
  lines.push(
    fb.source === 'world'
      ? 'source: contact impulses of the last step / (1/60 s), joint reactions'
      : "source: the server's contact impulses of the last step / (1/60 s), joint reactions",
  )
  return lines.join('\n')
}

/** Draw the diagram's arrows in world space; `scale` is CSS px per metre. */
export function drawFreeBody(ctx: CanvasRenderingContext2D, origin: Vec2, fb: FreeBody, scale: number): void {
  // A body's weight is always the same length whatever its mass: 2 m, or 100 px when zoomed out.
  const { unit, max } = arrowScale(len(fb.gravity), scale)
  const arrow = (from: Vec2, f: Vec2, color: string): void => {
    // Forces of many body weights (a block under a stack) are drawn at most 3 weights long.
    const l = Math.min(len(f) * unit, max)
    if (l < 1e-4) return
    const k = l / len(f)
    const tx = from.x + f.x * k
    const ty = from.y + f.y * k
    const head = Math.min(Math.max(0.25, 10 / scale), l * 0.4)
    const ux = (tx - from.x) / l
    const uy = (ty - from.y) / l
    ctx.strokeStyle = color
    ctx.fillStyle = color
    ctx.lineWidth = 2.5 / scale
    ctx.beginPath()
    ctx.moveTo(from.x, from.y)
    ctx.lineTo(tx, ty)
    ctx.stroke()
    ctx.beginPath()
    ctx.moveTo(tx, ty)
    ctx.lineTo(tx - ux * head - uy * head * 0.5, ty - uy * head + ux * head * 0.5)
    ctx.lineTo(tx - ux * head + uy * head * 0.5, ty - uy * head - ux * head * 0.5)
    ctx.closePath()
    ctx.fill()
  }
  arrow(origin, fb.gravity, '#f2c14e')
  for (const c of fb.contacts) {
    arrow(c.point, c.normal, '#4ecdc4')
    arrow(c.point, c.friction, '#ff6b6b')
  }
  for (const j of fb.joints) arrow(j.point, j.force, '#c792ea')
  arrow(origin, fb.net, '#ffffff')
}
