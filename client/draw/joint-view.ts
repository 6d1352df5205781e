/*
 * Joints as drawn this frame: a WireJoint (its kind and parameters, anchors in each body's frame)
 * placed on the poses the bodies have in this frame, so joints move exactly with their bodies
 * whether those come from the local engine or from interpolated snapshots. Both sandboxes build
 * their joint views here.
 */
import type { Vec2 } from '../../engine/index.ts'
import type { WireJoint } from '../../shared/index.ts'
import { toWorld } from '../input/index.ts'
import type { ViewBody, ViewJoint } from '../modes/index.ts'

/** Wrap an angle into (-pi, pi] (rad). */
export function wrapPi(angle: number): number {
  let a = angle % (2 * Math.PI)
  if (a > Math.PI) a -= 2 * Math.PI
  else if (a <= -Math.PI) a += 2 * Math.PI
  return a
}

/**
 * The view of joint `j` between the drawn bodies `a` (null for the world) and `b`, with its last
 * reaction force on b (N) when known; null when a body it needs is not drawn.
 */
export function viewJoint(
  j: WireJoint,
  a: ViewBody | null | undefined,
  b: ViewBody | undefined,
  force: Vec2 | null,
): ViewJoint | null {
  if (!b || (j.a !== 0 && !a)) return null
  const pa = a ? toWorld(a, j.ax, j.ay) : { x: j.ax, y: j.ay }
  const pb = toWorld(b, j.bx, j.by)
  const angleA = a ? a.angle : 0
  // The axis turns with body a; the translation is the anchors' separation along it.
  const c = Math.cos(angleA)
  const s = Math.sin(angleA)
  const axisX = c * j.ux - s * j.uy
  const axisY = s * j.ux + c * j.uy
  return {
    id: j.id,
    kind: j.kind,
    spec: j,
    ax: pa.x,
    ay: pa.y,
    bx: pb.x,
    by: pb.y,
    angleA,
    angle: wrapPi(b.angle - angleA - j.ref),
    axisX,
    axisY,
    translation: (pb.x - pa.x) * axisX + (pb.y - pa.y) * axisY,
    force,
  }
}

/** Build the views of every joint from a joint map and a body lookup (joints of missing bodies are left out). */
export function viewJoints(
  joints: Iterable<WireJoint>,
  body: (id: number) => ViewBody | undefined,
  force: (id: number) => Vec2 | null,
): ViewJoint[] {
  const out: ViewJoint[] = []
  for (const j of joints) {
    const v = viewJoint(j, j.a ? body(j.a) : null, body(j.b), force(j.id))
    if (v) out.push(v)
  }
  return out
}
