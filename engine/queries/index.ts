/*
 * Queries: exact answers about shapes without touching the state: ray casts against one shape
 * (ray-cast.ts), the GJK distance between two convex shapes and the shape cast built on it
 * (shape-distance.ts, shape-cast.ts), a callback-free ray cast through the dynamic tree
 * (tree-ray-cast.ts), and the world queries over them (world-queries.ts: closest and all-hits
 * rays, shape cast, AABB, point and shape overlaps, with Box2D's query filter). Depends on
 * collision/ (the tree) and the root files. The World's query methods (world/query-api.ts) are
 * built on WorldQueries.
 */
export {
  type CastOutput,
  makeCastOutput,
  type RayCastInput,
  rayCastCapsule,
  rayCastChainSegment,
  rayCastCircle,
  rayCastPolygon,
  rayCastSegment,
} from './ray-cast.ts'
export { shapeCast } from './shape-cast.ts'
export {
  makeDistanceOutput,
  makeShapeProxy,
  type ShapeProxy,
  shapeDistance,
  type Transform,
} from './shape-distance.ts'
export { TreeRayCast } from './tree-ray-cast.ts'
export {
  type AABB,
  DEFAULT_QUERY_FILTER,
  makeRayHit,
  proxyOf,
  type QueryFilter,
  type QueryGeometry,
  type QueryWorld,
  type RayHit,
  RayHitList,
  WorldQueries,
} from './world-queries.ts'
