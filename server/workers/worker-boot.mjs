// Starts a room worker from TypeScript source (tests, tsx): registers tsx's loader in the worker
// thread, then imports the entry (server/workers/room-worker.ts). The build ships dist/room-worker.js instead.
import { workerData } from 'node:worker_threads'
import { register } from 'tsx/esm/api'

register()
await import(workerData.entry)
