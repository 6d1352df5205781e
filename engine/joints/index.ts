/*
 * Joints: the Joint record and the per-step dispatch (joint.ts), each kind's math (revolute,
 * distance, mouse), what they share (joint-math.ts), the direct solver for trees of pins
 * (joint-tree.ts), and definitions to joints and back (joint-defs.ts). Depends on dynamics/.
 */

export { Joint, prepareJoints, solveJoints, warmStartJoints } from './joint.ts'
export { buildJoint, jointInfo, jointReaction, localPoint } from './joint-defs.ts'
export { JOINT_TYPE_NAMES, MOUSE } from './joint-math.ts'
export { JointTree, prepareJointTree, solveJointTree } from './joint-tree.ts'
