/*
 * Joints: the Joint record and the per-step dispatch (joint.ts), each kind's math (revolute,
 * distance, mouse), what they share (joint-math.ts), the direct solver for trees of pins
 * (joint-tree.ts), and definitions to joints and back (joint-defs.ts). Depends on dynamics/.
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
export { JointTree, prepareJointTree, solveJointTree } from './joint-tree.ts'
