/*
 * The server's snapshot path makes next to no garbage once warm: a room worker builds a frame of
 * every body and encodes it for every client twenty times a second, and with 10 busy rooms per
 * worker its garbage set how often the young-generation collector paused the shared loop tick
 * (bench:room-tick, Nov 24: 590 MB allocated in 2,100 ticks of 10 rooms, 55 scavenges of about
 * 1 ms and 8 mark-compacts of about 3 ms, in the tail that bench:capacity's tick p99 measures).
 *
 * Measured in its own process (tests/support/measure-allocation.ts): a 100-body pile that never sleeps,
 * five clients that acknowledge every snapshot, three steps per snapshot as at 20 Hz; per snapshot
 * the server-side work of Room.sendSnapshots without sockets: fillFrame, one encode, four
 * follows (the clients share the reference), five acks.
 * What a snapshot must allocate: the one encode's update list (kept until acknowledged) and the
 * stats objects, about 400 bytes. Bound: 1,024 bytes per snapshot; main before Nov 24 measured
 * 6.3 KB here: the frame's ensure() allocated a closure context on every put (V8 allocates a
 * function's context at entry when an inner arrow captures a variable), fillFrame an id array and
 * a boxed angle per body, and every ack a Map rehash.
 * The process runs with a larger inlining budget (--max-inlined-bytecode-size-cumulative=4000,
 * V8's default is 920) so the figure is the code's and not one JIT decision's: when V8 inlines
 * world.writePoses into fillFrame with the default budget, the budget runs out before atan2, so
 * each body's angle crosses a call boxed (its two arguments and result, 48 bytes a body, 5 KB per
 * snapshot here); compiled on its own, writePoses inlines atan2 and allocates nothing. Runs of this
 * test at the default budget saw the first, bench:room-tick's profile the second.
 */
import { dirname } from 'node:path'
import { fileURLToPath } from 'node:url'
import { describe, expect, it } from 'vitest'
import { measureAllocation } from '../../support/measure-allocation.ts'

const SNAPSHOTS = 500
const BOUND = 1024

describe('snapshot allocation', () => {
  it(`a warm snapshot of a 100-body room for 5 clients allocates less than ${BOUND} bytes`, async () => {
    const result = await measureAllocation({
      resolveDir: dirname(fileURLToPath(import.meta.url)),
      setup: `
import { buildScene, createWorld, pileScene } from '../../../engine/index.ts'
import { fillFrame } from '../../../server/rooms/room-wire.ts'
import { ByteWriter, QuantizedFrame, SnapshotEncoder } from '../../../shared/index.ts'
const world = createWorld({ enableSleep: false })
buildScene(world, pileScene(100))
const frame = new QuantizedFrame()
const clients = [new SnapshotEncoder(), new SnapshotEncoder(), new SnapshotEncoder(), new SnapshotEncoder(), new SnapshotEncoder()]
fillFrame(world, frame)
for (let i = 0; i < clients.length; i++) clients[i].reset(frame, world.tick)
const out = new ByteWriter()
let moved = 0
`,
      unit: `
  world.step()
  world.step()
  world.step()
  fillFrame(world, frame)
  const tick = world.tick
  out.reset()
  moved += clients[0].encode(out, frame, tick, 1 << 20).sent
  for (let i = 1; i < clients.length; i++) {
    if (!clients[i].follow(clients[0], frame, tick, 1 << 20)) throw new Error('client ' + i + ' did not follow')
  }
  for (let i = 0; i < clients.length; i++) if (!clients[i].ack(tick)) throw new Error('ack refused')
  if (moved === 0 && tick > 600) throw new Error('nothing moved: not a busy room')
`,
      units: SNAPSHOTS,
      warmup: 1000,
      reportAbove: BOUND,
      flags: ['--max-inlined-bytecode-size-cumulative=4000'],
    })
    const perSnapshot = result.heapGrowth / result.units
    console.log(
      `snapshot allocation: ${perSnapshot.toFixed(0)} bytes per snapshot (least of 3 rounds of ${result.units}), ` +
        `${result.gcCount} collections ${JSON.stringify(result.gcKinds)}` +
        (result.allocators.length ? `; allocating: ${JSON.stringify(result.allocators)}` : ''),
    )
    expect(result.gcCount, JSON.stringify(result.allocators)).toBe(0)
    expect(perSnapshot, JSON.stringify(result.allocators)).toBeLessThan(BOUND)
  })
})
