/*
 * Replays in the page: the picker and page, the player's timeline (a log indexed by keyframes, with
 * seek), its own snapshots, and the replay sandbox that plays a log through shared/'s
 * RoomSimulation.
 */
export { ReplayPage } from './replay-page.ts'
export { ReplayPlayer, readLog } from './replay-player.ts'
