/*
 * Concord's physics engine: the public surface. Nothing outside engine/ imports anything else from
 * this folder. See engine/README.md for the rules and the contract.
 */

export {
  box,
  type CircleShape,
  circle,
  computeMass,
  type MassData,
  type PolygonShape,
  polygon,
  type Shape,
} from './collision/index.ts'
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
export { atan2, cos, PI, sin, TRIG_LIMIT, TWO_PI, type Vec2, wrapAngle } from './math.ts'
export { Prng } from './prng.ts'
export {
  buildScene,
  CHAIN_LINK_LENGTH,
  CHAIN_TOP,
  cardHouseScene,
  chainBridgeScene,
  emptyScene,
  groundDef,
  hangingChainScene,
  heavyOnLightScene,
  jointsScene,
  MACHINES_LAYOUT,
  machinesScene,
  newtonsCradleScene,
  pileScene,
  pyramidScene,
  ragdollScene,
  rampScene,
  regularPolygon,
  SCENES,
  type SceneBlueprint,
  towerScene,
  wreckingBallScene,
} from './scenes/index.ts'
export { FixedStepper } from './stepper.ts'
export type {
  BodyDef,
  BodyId,
  BodyType,
  ContactInfo,
  DistanceJointDef,
  JointBreakDef,
  JointDef,
  JointEvents,
  JointId,
  JointInfo,
  JointReaction,
  MotorJointDef,
  MouseJointDef,
  PrismaticJointDef,
  RevoluteJointDef,
  WeldJointDef,
  WheelJointDef,
  WorldDef,
} from './types.ts'
export {
  createWorld,
  DEFAULT_WORLD_DEF,
  loadWorld,
  POSE_ANGLE,
  POSE_AWAKE,
  POSE_ID,
  POSE_STATIC,
  POSE_STRIDE,
  POSE_TYPE,
  POSE_X,
  POSE_Y,
  resolveWorldDef,
  SAVE_FORMAT_VERSION,
  World,
  WorldLoadError,
} from './world/index.ts'
