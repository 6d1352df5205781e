/*
 * Input: the pointer tools (mouse, pen and touch through Pointer Events), hit testing of bodies,
 * the keyboard shortcuts table, and what the spawn tools drop.
 */

export { EditPanel } from './edit-panel.ts'
export { EditTool, editable } from './edit-tool.ts'
export { DRIVE_SPEED, driveSpeed, JOINT_DEFAULTS, JointPanel, type JointSettings } from './joint-settings.ts'
export { bodyRadius, pickBody, shapeRadius, shapeVertices, toWorld } from './picking.ts'
export { helpIntro, helpRows, type ShortcutAction, shortcutFor } from './shortcuts.ts'
export { SpawnPanel } from './spawn-settings.ts'
export { TOOL_COMMANDS, TOOLS, ToolController, type ToolName } from './tools.ts'
