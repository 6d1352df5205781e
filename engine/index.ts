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
export { CHAIN_LINK_LENGTH, CHAIN_TOP, hangingChainScene, ragdollScene } from './joint-stress-scenes.ts'
export { MACHINES_LAYOUT, machinesScene } from './machine-scenes.ts'
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
  type CircleShape,
  circle,
  computeMass,
  type MassData,
  type PolygonShape,
  polygon,
  type Shape,
} from './shapes.ts'
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
export { createWorld, loadWorld, World } from './world.ts'
export { POSE_STRIDE } from './world-api.ts'
export { DEFAULT_WORLD_DEF, resolveWorldDef } from './world-store.ts'
