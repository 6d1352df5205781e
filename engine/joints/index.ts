/*
 * Joints: the Joint record and the per-step dispatch (joint.ts), each kind's math (revolute,
 * distance, mouse), what they share (joint-math.ts), the direct solver for trees of pins
 * (joint-tree.ts), definitions to joints and back (joint-defs.ts), and settings changed after
 * creation (joint-settings.ts). Depends on dynamics/.
 */

export { Joint, prepareJoints, solveJoints, warmStartJoints } from './joint.ts'
export {
  buildJoint,
  exceedsBreak,
  jointAngle,
  jointDef,
  jointInfo,
  jointReaction,
  jointSpeed,
  jointTranslation,
  localPoint,
} from './joint-defs.ts'
export { DISTANCE, JOINT_TYPE_NAMES, MOTOR, MOUSE, PRISMATIC, REVOLUTE, WHEEL } from './joint-math.ts'
export { applyJointSettings, JOINT_SETTINGS } from './joint-settings.ts'
export { JointTree, prepareJointTree, solveJointTree } from './joint-tree.ts'
