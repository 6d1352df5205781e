/*
 * What the server, the browser client and the bots all run, in three parts, each with an index.ts
 * that lists its exports by name:
 *
 * - protocol/  the wire: message types, codec, validation, quantization, snapshots (PROTOCOL.md).
 * - sim/       the deterministic room simulation, world commands, the lockstep tick stream, and the
 *              DOM-free followers of a room (snapshot mirror, lockstep and predict clients).
 * - replay/    the log format, its reader and the runner that replays a log.
 *
 * Outside shared/, code imports this file only. Inside, protocol <- sim <- replay (a part imports
 * only the parts before it, through their index.ts).
 */
export * from './protocol/index.ts'
export * from './replay/index.ts'
export * from './sim/index.ts'
