/*
 * The contact manifold: what the narrowphase tells the solver about two touching (or nearly
 * touching) shapes. Manifolds are reused objects, filled in place, so collision allocates nothing.
 *
 * Conventions (Box2D v3):
 * - `normal` is a world-space unit vector pointing from shape A to shape B.
 * - Each point is the midpoint between the two surfaces, in world space, with `separation`
 *   negative when the shapes overlap (m). Points are kept while separation < speculative distance.
 * - `id` is a feature key (which vertex/edge of each shape made the point) that stays the same
 *   across steps while the same features touch; the solver matches impulses by it (warm starting).
 */

/** One contact point of a manifold. */
export class ManifoldPoint {
  /** World point halfway between the surfaces (m). */
  x = 0
  y = 0
  /** Signed distance along the normal, negative when overlapping (m). */
  separation = 0
  /** Feature key, stable across steps while the same features touch. */
  id = 0
}

/** Up to two contact points sharing one normal. */
export class Manifold {
  /** World unit normal from A to B. */
  normalX = 0
  normalY = 0
  /** Number of valid points, 0..2. */
  pointCount = 0
  readonly points: [ManifoldPoint, ManifoldPoint] = [new ManifoldPoint(), new ManifoldPoint()]
}

/** Makes a feature key from two feature indices (each 0..255). */
export function makeFeatureId(a: number, b: number): number {
  return ((a & 0xff) << 8) | (b & 0xff)
}
