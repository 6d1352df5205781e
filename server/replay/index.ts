/*
 * Recording and replay on the server: a recorder per room (append-only logs with keyframes and
 * hashes), the server's recordings and the replay directory's files, crash recovery from a log,
 * and the replay command line (`npm run replay`).
 */
export { RoomRecorder } from './recorder.ts'
export { Recordings } from './recordings.ts'
export { replayLog } from './replay-tool.ts'
