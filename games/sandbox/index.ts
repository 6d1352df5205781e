/*
 * The sandbox game: Concord's building game (spawn, grab, pin, rope, delete, scenes, pause, step,
 * reset, gravity; weld, hinge, spring, slider, wheel, jointMotor and editJoint; edit, transform, duplicate and
 * deleteMany; undo and redo of each player's own actions) written on the game module API; its
 * commands are reusable by other games.
 */
export {
  editCommands,
  editRefusal,
  filterLayer,
  layerFilter,
  MAX_DELETE_MANY,
  MAX_LAYER,
  MAX_SCALE,
  MIN_SCALE,
} from './edit-commands.ts'
export {
  EDITABLE_JOINT_SETTINGS,
  type EditJointArgs,
  editJointSettings,
  jointCommands,
  MAX_JOINT_MOTOR_SPEED,
} from './joint-commands.ts'
export { MIN_TICKS_BETWEEN_LOADS, sandbox, sandboxCommands } from './sandbox-game.ts'
export {
  captureBodies,
  captureJoints,
  recordAction,
  recordJoint,
  undoCommands,
} from './undo-commands.ts'
