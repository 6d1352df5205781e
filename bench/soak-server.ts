/*
 * The server process of the soak (bench/soak.ts starts it with an IPC channel, so that it can
 * SIGKILL it at the end): a timed server (server-load.ts startTimedServer) recording to the replay
 * directory the soak gives, with the soak's rooms opened on request and its loop and memory
 * readings answered on request. Arguments: WORKERS REPLAY_KEEP REPLAY_DIR.
 * Messages in: { id, op: 'open', names } (a pile of 100 never-sleeping bodies each), { id, op:
 * 'bodies', names }, { id, op: 'players' }, { id, op: 'sample' }; each is answered { id, value }.
 * Out first: { op: 'ready', url }.
 */
import { awakePile, loopStats, memoryMb, openRoom, quantile, startTimedServer } from './server-load.ts'

const [workersText, keepText, replayDir] = process.argv.slice(2)
const workers = Number(workersText)
const keep = Number(keepText)
if (!Number.isInteger(workers) || workers < 0 || !Number.isInteger(keep) || keep < 1 || !replayDir) {
  throw new Error(
    `usage: soak-server.ts WORKERS REPLAY_KEEP REPLAY_DIR, got ${process.argv.slice(2).join(' ')}`,
  )
}
if (!process.send)
  throw new Error('soak-server.ts runs as a child of bench/soak.ts (it needs an IPC channel)')
const send = process.send.bind(process)

// Rooms close 5 s after their last client leaves, as by default, so the churn rooms come and go.
const timed = await startTimedServer(workers, 5, keep, replayDir)
const { server } = timed
const take = loopStats(timed)
const blueprint = awakePile(100)

const bodiesOf = (name: string): number =>
  server.pool
    ? (server.pool.summaries().find((r) => r.name === name)?.bodies ?? 0)
    : (server.rooms.get(name)?.world.bodyCount ?? 0)

type Request = { id: number } & (
  | { op: 'open'; names: string[] }
  | { op: 'bodies'; names: string[] }
  | { op: 'players' }
  | { op: 'sample' }
)

function answer(request: Request): unknown {
  switch (request.op) {
    case 'open':
      for (const name of request.names) openRoom(server, name, blueprint)
      return null
    case 'bodies':
      return request.names.map(bodiesOf)
    case 'players':
      return server.host.playerCount
    case 'sample': {
      const ticks = take()
      const mem = memoryMb()
      return {
        rssMb: mem.rss,
        heapMb: mem.heap,
        workerHeapMb: ticks.workerHeapMb.reduce((a, b) => a + b, 0),
        tickMsP50: quantile(ticks.wall, 0.5),
        tickMsP99: quantile(ticks.wall, 0.99),
        cpuMsP99: quantile(ticks.cpu, 0.99),
        overruns: ticks.overruns,
        rooms: server.pool ? server.pool.summaries().length : server.rooms.list().length,
        clients: server.host.playerCount,
      }
    }
  }
}

process.on('message', (request: Request) => send({ id: request.id, value: answer(request) }))
// The soak ends this process with SIGKILL (or it ends when the soak does).
process.on('disconnect', () => process.exit(0))
send({ op: 'ready', url: server.url, pid: process.pid })
