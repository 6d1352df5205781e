/*
 * Collision: shapes and their mass, polygon geometry, the narrowphase manifolds for every pair of
 * shape kinds, the swept distance for continuous collision, the dynamic AABB tree, the broadphase
 * and the contacts' pair map, and the convex hull and concave decomposition that make shapes.
 * Depends only on the engine's root files (math, constants).
 */
export { BroadPhase, IdBuffer, PairBuffer, sortKeys } from './broad-phase.ts'
export { collideChainSegmentAt, collideGeometry, collideGeometryAt, type Pose } from './collide.ts'
export { DECOMPOSE_MIN_WIDTH, decompose, decomposeOutline, MAX_OUTLINE_POINTS } from './decompose.ts'
export { type DynamicTree, NULL_NODE } from './dynamic-tree.ts'
export { Manifold, type ManifoldPoint } from './manifold.ts'
export { PairMap } from './pair-map.ts'
export { polygonGeometry, VERTEX_X, VERTEX_Y } from './polygon-geometry.ts'
export {
  box,
  type CapsuleShape,
  type ChainSegmentShape,
  type ChainShape,
  type CircleShape,
  capsule,
  chain,
  chainSegmentShape,
  circle,
  combineMass,
  computeMass,
  convexPolygon,
  isSlender,
  type MassData,
  type PolygonalShape,
  type PolygonShape,
  polygon,
  type SegmentShape,
  type Shape,
  segment,
  slenderAxis,
} from './shapes.ts'
export {
  CORE,
  DISTANCE,
  EDGE,
  FRACTION,
  maxEdgeSeparation,
  pose,
  poseAt,
  sweep,
  sweptDistance,
  transformVertices,
  verticesA,
  verticesB,
} from './swept-distance.ts'
