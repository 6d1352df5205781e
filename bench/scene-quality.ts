/*
 * How a comparison scene ended in one engine: the quality column next to every speed figure, so
 * speed is never bought with a collapsing stack.
 *
 * From the bodies' start (their definitions) and end (readBodies) we measure the largest drift,
 * the fastest body, the top body's shift, the bodies that left the ground or the container, and
 * for joint grids how far any joint pulled apart (a revolute joint keeps the two body centres at
 * most their creation distance apart: any excess is the solver's error). The verdict per kind:
 * a pyramid or tower 'stood' while no box moved 1 m; a pile or rain is 'contained' while no body
 * escaped; a grid 'held' while no joint stretched 5 cm.
 */
import type { BodyDef, SceneBlueprint } from '../engine/index.ts'
import type { BenchSceneKind } from './bench-scenes.ts'

/** A stack stands while no box moved this far from its start (m). */
const STANDING_DRIFT = 1
/** A joint grid holds while no joint is stretched this far (m). */
const HELD_STRETCH = 0.05

/** How a scene looks at the end of the run, in one engine. */
export interface SceneQuality {
  /** Largest distance any dynamic body moved from where it was created (m). */
  maxDrift: number
  /** Fastest dynamic body at the end (m/s). */
  maxSpeed: number
  /** Final minus initial x of the last-created blueprint body: the top box of a stack (m). */
  topDx: number
  /** Final minus initial y of that body (m). */
  topDy: number
  /** Dynamic bodies below the ground or outside the container's walls. */
  escaped: number
  /** Largest revolute joint stretch (m); 0 without joints. */
  maxStretch: number
  /** Dynamic bodies awake at the end. */
  awake: number
  /** Simulated seconds until every body slept (sleep on), or null if they never all did. */
  sleptAfter: number | null
  /** 'stood' | 'FELL', 'contained' | 'N ESCAPED', 'held' | 'STRETCHED'. */
  verdict: string
}

/** All bodies of a run in creation order: the blueprint's, then the arrivals'. */
export function allBodies(blueprint: SceneBlueprint, arrivals: readonly { def: BodyDef }[]): BodyDef[] {
  return [...blueprint.bodies, ...arrivals.map((a) => a.def)]
}

function containerHalfWidth(bodies: readonly BodyDef[]): number {
  let wall = 0
  for (const def of bodies) {
    if (
      def.type === 'static' &&
      def.position &&
      def.shape.box &&
      def.shape.box.halfHeight > def.shape.box.halfWidth
    ) {
      wall = Math.max(wall, Math.abs(def.position.x))
    }
  }
  return wall > 0 ? wall : Number.POSITIVE_INFINITY
}

/** Measures the end state of one engine's run (end: readBodies, 4 numbers per body). */
export function measureQuality(
  kind: BenchSceneKind,
  blueprint: SceneBlueprint,
  bodies: readonly BodyDef[],
  end: Float64Array,
  awake: number,
  sleptAfter: number | null,
): SceneQuality {
  const wallX = containerHalfWidth(bodies)
  let maxDrift = 0
  let maxSpeed = 0
  let escaped = 0
  bodies.forEach((def, i) => {
    if ((def.type ?? 'dynamic') === 'static' || i * 4 >= end.length) return
    const [x, y, vx, vy] = end.subarray(i * 4, i * 4 + 4)
    const x0 = def.position?.x ?? 0
    const y0 = def.position?.y ?? 0
    maxDrift = Math.max(maxDrift, Math.hypot(x - x0, y - y0))
    maxSpeed = Math.max(maxSpeed, Math.hypot(vx, vy))
    if (!(y > -0.25 && Math.abs(x) < wallX)) escaped++
  })
  let maxStretch = 0
  for (const joint of blueprint.joints ?? []) {
    if (joint.type !== 'revolute') continue
    const b = joint.bodyB
    const pb = { x: end[b * 4], y: end[b * 4 + 1] }
    const bb = bodies[b].position ?? { x: 0, y: 0 }
    const a = joint.bodyA
    const pa = a === null ? joint.anchor : { x: end[a * 4], y: end[a * 4 + 1] }
    const ba = a === null ? joint.anchor : (bodies[a].position ?? { x: 0, y: 0 })
    const rest =
      Math.hypot(ba.x - joint.anchor.x, ba.y - joint.anchor.y) +
      Math.hypot(bb.x - joint.anchor.x, bb.y - joint.anchor.y)
    maxStretch = Math.max(maxStretch, Math.hypot(pb.x - pa.x, pb.y - pa.y) - rest)
  }
  const last = blueprint.bodies.length - 1
  const top = blueprint.bodies[last].position ?? { x: 0, y: 0 }
  const topDx = end[last * 4] - top.x
  const topDy = end[last * 4 + 1] - top.y
  let verdict: string
  if (kind === 'pyramid' || kind === 'tower')
    verdict = maxDrift < STANDING_DRIFT && escaped === 0 ? 'stood' : 'FELL'
  else if (kind === 'grid') verdict = maxStretch < HELD_STRETCH && escaped === 0 ? 'held' : 'STRETCHED'
  else verdict = escaped === 0 ? 'contained' : `${escaped} ESCAPED`
  return { maxDrift, maxSpeed, topDx, topDy, escaped, maxStretch, awake, sleptAfter, verdict }
}
