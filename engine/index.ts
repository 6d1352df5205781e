/*
 * Concord's physics engine: the public surface. Nothing outside engine/ imports anything else from
 * this folder. See engine/README.md for the rules and the contract.
 */

export {
  HIT_EVENT_SPEED,
  LINEAR_SLOP,
  MAX_LINEAR_SPEED,
  MAX_POLYGON_VERTICES,
  MAX_POSITION,
  MAX_ROTATION,
  MAX_SHAPE_EXTENT,
  SPECULATIVE_DISTANCE,
  STEP_SECONDS,
} from './constants.ts'
export type {
  ContactEvents,
  ContactHitEvent,
  ContactTouchEvent,
  SensorEvent,
  SensorEvents,
} from './events.ts'
export { CHAIN_LINK_LENGTH, CHAIN_TOP, hangingChainScene, ragdollScene } from './joint-stress-scenes.ts'
export { atan2, cos, PI, sin, TRIG_LIMIT, TWO_PI, type Vec2, wrapAngle } from './math.ts'
export { Prng } from './prng.ts'
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
  box,
  type CapsuleShape,
  type CircleShape,
  capsule,
  circle,
  combineMass,
  computeMass,
  type MassData,
  type PolygonalShape,
  type PolygonShape,
  polygon,
  type SegmentShape,
  type Shape,
  segment,
} from './shapes.ts'
export { FixedStepper } from './stepper.ts'
export type {
  BodyDef,
  BodyId,
  BodyType,
  CompoundBodyDef,
  ContactInfo,
  DistanceJointDef,
  ExplosionDef,
  Filter,
  JointDef,
  JointId,
  JointInfo,
  JointReaction,
  MouseJointDef,
  RevoluteJointDef,
  ShapeDef,
  ShapeId,
  WorldDef,
} from './types.ts'
export { createWorld, loadWorld, World } from './world.ts'
export { POSE_STRIDE } from './world-api.ts'
export { DEFAULT_WORLD_DEF, resolveWorldDef } from './world-store.ts'
