/*
 * The page's side of the wire: the WebSocket connection with reconnect, the input outbox, snapshot
 * interpolation and pose tracks, the server's step time for the HUD, and spawns followed until the
 * server answers.
 */
export { Connection } from './connection.ts'
export { InputOutbox } from './input-outbox.ts'
export { type Pose, SnapshotTimeline } from './interpolation.ts'
export { ServerStats } from './server-stats.ts'
export { MAX_SENDS } from './spawn-tracker.ts'
