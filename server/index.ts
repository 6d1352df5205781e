/*
 * The server as other layers use it (benchmarks, the bots' load tools): starting a server, its
 * settings, and the room, recording and worker pieces the benchmarks drive without sockets. The
 * server's own folders (net, http, rooms, workers, replay, hosting, config) are listed in
 * server/README.md; main.ts is the command line.
 */
export { loadConfig, SETTINGS } from './config/index.ts'
export { createMetrics } from './hosting/index.ts'
export { Recordings, RoomRecorder, replayLog } from './replay/index.ts'
export { handleRoomMessage, type Room, RoomManager, type RoomPlayer } from './rooms/index.ts'
export { type RunningServer, startServer } from './server.ts'
export { Outbox, StretchTimer, WorkerConnection } from './workers/index.ts'
