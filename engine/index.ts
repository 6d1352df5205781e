/*
 * Concord's physics engine: the public surface. Nothing outside engine/ imports anything else from
 * this folder. See engine/README.md for the rules and the contract.
 */

export {
  LINEAR_SLOP,
  MAX_LINEAR_SPEED,
  MAX_POLYGON_VERTICES,
  MAX_POSITION,
  MAX_ROTATION,
  MAX_SHAPE_EXTENT,
  SPECULATIVE_DISTANCE,
  STEP_SECONDS,
} from './constants.ts'
export { DECOMPOSE_MIN_WIDTH, decompose, MAX_OUTLINE_POINTS } from './decompose.ts'
export { computeHull, HULL_COLLINEAR_DISTANCE, HULL_WELD_DISTANCE, MAX_HULL_INPUT } from './hull.ts'
export { CHAIN_LINK_LENGTH, CHAIN_TOP, hangingChainScene, ragdollScene } from './joint-stress-scenes.ts'
export { atan2, cos, PI, sin, TRIG_LIMIT, TWO_PI, type Vec2, wrapAngle } from './math.ts'
export { Prng } from './prng.ts'
export {
  type CapsuleGeometry,
  type CastOutput,
  type ChainSegmentGeometry,
  type CircleGeometry,
  checkRayInput,
  makeCastOutput,
  type PolygonGeometry,
  type RayCastInput,
  rayCastCapsule,
  rayCastChainSegment,
  rayCastCircle,
  rayCastPolygon,
  rayCastSegment,
  type SegmentGeometry,
} from './ray-cast.ts'
export { SAVE_FORMAT_VERSION, WorldLoadError } from './save-format.ts'
export {
  buildScene,
  cardHouseScene,
  chainBridgeScene,
  emptyScene,
  groundDef,
  heavyOnLightScene,
  jointsScene,
  newtonsCradleScene,
  pileScene,
  pyramidScene,
  rampScene,
  regularPolygon,
  SCENES,
  type SceneBlueprint,
  towerScene,
  wreckingBallScene,
} from './scenes.ts'
export {
  CAST_MAX_ITERATIONS,
  CAST_TOLERANCE,
  checkShapeCastInput,
  type ShapeCastPairInput,
  shapeCast,
} from './shape-cast.ts'
export {
  capsuleProxy,
  circleProxy,
  type DistanceOutput,
  IDENTITY,
  makeDistanceOutput,
  makeShapeProxy,
  polygonProxy,
  type ShapeProxy,
  segmentProxy,
  shapeDistance,
  type Transform,
} from './shape-distance.ts'
export {
  box,
  type CircleShape,
  circle,
  computeMass,
  type MassData,
  type PolygonShape,
  polygon,
  type Shape,
} from './shapes.ts'
export { FixedStepper } from './stepper.ts'
export { TreeRayCast } from './tree-ray-cast.ts'
export type {
  BodyDef,
  BodyId,
  BodyType,
  ContactInfo,
  DistanceJointDef,
  JointDef,
  JointId,
  JointInfo,
  JointReaction,
  MouseJointDef,
  RevoluteJointDef,
  WorldDef,
} from './types.ts'
export { createWorld, loadWorld, World } from './world.ts'
export { POSE_STRIDE } from './world-api.ts'
export {
  type AABB,
  castGeometry,
  DEFAULT_QUERY_FILTER,
  geometryBox,
  makeRayHit,
  proxyOf,
  type QueryFilter,
  type QueryGeometry,
  type QueryWorld,
  type RayHit,
  RayHitList,
  shouldQueryShape,
  WorldQueries,
} from './world-queries.ts'
export { DEFAULT_WORLD_DEF, resolveWorldDef } from './world-store.ts'
