/*
 * The browser client as other layers use it: the replay player's timeline, which the replay
 * benchmarks time in Node. The page itself starts at main.ts (the URL picks the mode); the folders
 * (modes, net, draw, input, replay) are described in client/README.md.
 */

export { Camera, Renderer, viewJoints } from './draw/index.ts'
export type { ViewBody } from './modes/index.ts'
export { ReplayPlayer, readLog } from './replay/index.ts'
