/*
 * Rooms on worker threads: the pool and its link to each worker (main thread), the worker thread
 * itself, the messages between them, the worker's outbox for players whose sockets live on the
 * main thread, and per-thread CPU time.
 */
export { StretchTimer } from './thread-cpu.ts'
export { Outbox, WorkerConnection } from './worker-outbox.ts'
export { WorkerPool } from './worker-pool.ts'
export type { RoomSummary } from './worker-protocol.ts'
