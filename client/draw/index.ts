/*
 * Drawing: the canvas renderer (HiDPI, y up), the camera, joints, bodies of a world stepped in the
 * page, the HUD, and the lab's free-body diagram and plot. Draws what the modes hand it; never
 * talks to the server.
 */
export { Camera } from './camera.ts'
export { FpsMeter, hudText } from './hud.ts'
export { viewJoints } from './joint-view.ts'
export { computeFreeBody, describeFreeBody, type FreeBody, labFromServer, labFromWorld } from './lab.ts'
export { LabPlot } from './lab-plot.ts'
export { type DebugLayers, Renderer, type ToolOverlay } from './renderer.ts'
export { WorldView } from './world-view.ts'
