/*
 * Motion measures shared by the engine tests and bench/scene-side-effects.ts. The script steps any
 * engine folder (an older version, a branch's copy), so these read only World methods every
 * version has.
 */

/** The part of a World these measures read. */
export interface MovingWorld {
  step(): void
  bodyIds(): Iterable<number>
  getPosition(id: number): { x: number; y: number }
  getLinearVelocity(id: number): { x: number; y: number }
  getAngularVelocity(id: number): number
}

/** Fastest linear speed (m/s) and fastest angular speed (rad/s) of any body. */
export function fastest(world: MovingWorld): { v: number; w: number } {
  let v = 0
  let w = 0
  for (const id of world.bodyIds()) {
    const u = world.getLinearVelocity(id)
    v = Math.max(v, Math.hypot(u.x, u.y))
    w = Math.max(w, Math.abs(world.getAngularVelocity(id)))
  }
  return { v, w }
}

/** Steps `before` times, then `after` more: the largest distance any of `ids` moved over the `after` steps (m). */
export function driftOver(world: MovingWorld, ids: readonly number[], before: number, after: number): number {
  for (let i = 0; i < before; i++) world.step()
  const start = ids.map((id) => world.getPosition(id))
  for (let i = 0; i < after; i++) world.step()
  let drift = 0
  ids.forEach((id, k) => {
    const p = world.getPosition(id)
    drift = Math.max(drift, Math.hypot(p.x - start[k].x, p.y - start[k].y))
  })
  return drift
}
