/*
 * Negative zero from a client. MessagePack carries -0 as a float64 (0xcb 80 00 .. 00), and the
 * schema accepts it as a finite number, but the server writes every whole number as an integer:
 * the log (and the lockstep stream) said 0 where the room had applied -0. A body spawned with
 * vx, w or angle -0 (or a polygon vertex at -0) then differs in its bits from the replayed one, so
 * the log's own hash checkpoints no longer matched it: `npm run replay -- --verify` failed and
 * crash recovery refused the log. Against a real server: spawns whose fields are -0 on the wire,
 * then the log, closed cleanly, replays with every hash and keyframe matching.
 */
import { mkdtemp, readFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { listLogNames } from '../../../server/replay/replay-files.ts'
import { replayLog } from '../../../server/replay/replay-tool.ts'
import type { RunningServer } from '../../../server/server.ts'
import { type ClientMessage, encodeMessage } from '../../../shared/index.ts'
import { startTestServer } from '../../support/test-server.ts'

/** A number no message holds otherwise, replaced by -0 in the encoded bytes: float64 1.25. */
const MARK = 1.25
const MARK_BYTES = Buffer.from('cb3ff4000000000000', 'hex')
const NEGATIVE_ZERO_BYTES = Buffer.from('cb8000000000000000', 'hex')

/** `message` encoded with every MARK written as a float64 -0. */
function withNegativeZeros(message: ClientMessage): Buffer {
  const bytes = Buffer.from(encodeMessage(message))
  for (let at = bytes.indexOf(MARK_BYTES); at >= 0; at = bytes.indexOf(MARK_BYTES, at + 9))
    NEGATIVE_ZERO_BYTES.copy(bytes, at)
  return bytes
}

let server: RunningServer | null = null
afterAll(async () => {
  await server?.close()
})

describe('negative zeros in commands', { timeout: 30_000 }, () => {
  it('are applied as the log records them: the log replays with every hash matching', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-negzero-'))
    server = await startTestServer({ workers: 1, record: true, replayDir: dir, keyframeTicks: 60 })
    const bot = await BotClient.connect({ url: server.url, room: 'zero', name: 'zero' })
    const circle = { type: 'circle' as const, radius: 0.5 }
    const polygon = { type: 'polygon' as const, v: [MARK, MARK, 1, 0, 0, 1] }
    const spawns = [
      { k: 'spawn' as const, shape: circle, x: 3, y: 5, vx: MARK, vy: 1, w: MARK, angle: MARK },
      { k: 'spawn' as const, shape: polygon, x: -3, y: 2, vx: MARK },
    ]
    spawns.forEach((cmd, i) => {
      bot.ws.send(withNegativeZeros({ t: 'input', seq: i + 1, cmd }))
    })
    await bot.waitFor(() => bot.mirror.bodies.size >= 3, 'the spawned bodies')
    const start = bot.mirror.tick
    // Two hash checkpoints and keyframes after the spawns.
    await bot.waitFor(() => bot.mirror.tick > start + 130, 'two checkpoints')
    await bot.close()
    await server.close()
    server = null
    const name = (await listLogNames(dir)).find((n) => n.startsWith('zero-'))!
    const report = await replayLog(await readFile(join(dir, name)), { verify: true })
    expect(report.commands).toBe(2)
    expect(report.hashesChecked).toBeGreaterThanOrEqual(2)
    expect(report.divergence).toBeNull()
  })
})
