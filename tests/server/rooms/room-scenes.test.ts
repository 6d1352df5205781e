/*
 * Scene files in rooms over real sockets (rooms on worker threads, as `npm start` runs them):
 * POST /scenes keeps a file and answers its id, GET /scenes/ID gives it back byte for byte; the
 * room command openScene builds it in the room (every body where the file puts it), saveScene
 * writes the room's world back, and a world opened and saved again is the file uploaded (same
 * bytes, so the same id); refusals name the field or the reason; a lockstep client follows the
 * load without a desync, and the room's replay log verifies across it.
 */
import { mkdtemp, readdir, readFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { LockstepBot } from '../../../bots/lockstep-bot.ts'
import { buildScene as buildBlueprint, createWorld, machinesScene, pileScene } from '../../../engine/index.ts'
import { parseScene, saveScene, sceneText } from '../../../games/index.ts'
import { replayLog } from '../../../server/replay/index.ts'
import type { RunningServer } from '../../../server/server.ts'
import { cssColor, type ErrorMessage, type ServerMessage } from '../../../shared/index.ts'
import { startTestServer } from '../../support/test-server.ts'
import { documentedFields } from '../protocol/doc-tables.ts'

let server: RunningServer
let replayDir: string

beforeAll(async () => {
  replayDir = await mkdtemp(join(tmpdir(), 'concord-scene-rec-'))
  const sceneDir = await mkdtemp(join(tmpdir(), 'concord-scenes-'))
  server = await startTestServer({ record: true, replayDir, sceneDir, maxBodies: 200, maxSavedScenes: 3 })
})
afterAll(async () => {
  await server?.close()
})

const http = (path: string, init?: RequestInit) => fetch(`${server.url}${path}`, init)
const post = (body: string) => http('/scenes', { method: 'POST', body })

/** Colours of the uploaded files' bodies: every third body has one, the rest none. */
const COLORS = ['#ff8800', '#2a9d8f', '#e63946']
const colorOf = (id: number): string | undefined => (id % 3 === 0 ? COLORS[(id / 3) % 3] : undefined)

/** The machines scene (every joint kind), stepped a little, as a scene file named `name`, some bodies coloured. */
function machinesText(name: string): string {
  const world = createWorld()
  buildBlueprint(world, machinesScene())
  for (let i = 0; i < 30; i++) world.step()
  return sceneText(saveScene(world, { name, colorOf }))
}

/** The error answering `seq`. */
async function errorFor(bot: BotClient, seq: number): Promise<ErrorMessage> {
  let found: ErrorMessage | undefined
  await bot.waitFor(() => {
    found = bot.received.find((m): m is ErrorMessage => m.t === 'error' && m.seq === seq)
    return found !== undefined
  }, `the error for seq ${seq}`)
  return found as ErrorMessage
}

describe('scene files in rooms', { timeout: 90_000 }, () => {
  it('keeps, serves and refuses files over HTTP, naming the field', async () => {
    const text = machinesText('http')
    const kept = await post(text)
    expect(kept.status).toBe(201)
    const { id } = (await kept.json()) as { id: string }
    expect(id).toMatch(/^[0-9a-f]{16}$/)
    const served = await http(`/scenes/${id}`)
    expect(served.status).toBe(200)
    expect(served.headers.get('content-disposition')).toBe(`attachment; filename="scene-${id}.json"`)
    expect(await served.text()).toBe(text)
    // The same file again keeps one copy under the same id.
    expect(((await (await post(text)).json()) as { id: string }).id).toBe(id)
    const zeroRadius = text.replace('"type":"circle","radius":0.4', '"type":"circle","radius":0')
    expect(zeroRadius).not.toBe(text)
    const refusals: Array<[string, number, string]> = [
      ['{"format":', 400, 'the scene file is not JSON'],
      [zeroRadius, 400, '.shapes[0].radius must be > 0'],
      [text.replace('"version":1', '"version":7'), 400, 'version 7 is not supported'],
      [`${text}${' '.repeat(4 * 1024 * 1024)}`, 413, 'a scene file is at most 4194304 bytes'],
    ]
    for (const [body, status, reason] of refusals) {
      const res = await post(body)
      expect(res.status, reason).toBe(status)
      expect(await res.text()).toContain(reason)
    }
    expect((await http('/scenes/not-an-id')).status).toBe(400)
    const missing = await http('/scenes/0123456789abcdef')
    expect([missing.status, await missing.text()]).toEqual([
      404,
      'no saved scene 0123456789abcdef on this server\n',
    ])
    expect((await http('/scenes', { method: 'GET' })).status).toBe(405)
  })

  it('opens a kept scene in a room, saves it back identical, and a lockstep client and the replay follow', async () => {
    const room = 'scenes'
    const text = machinesText(room)
    const { id } = (await (await post(text)).json()) as { id: string }
    const player = await BotClient.connect({ url: server.url.replace('http', 'ws'), room, name: 'p' })
    const follower = await LockstepBot.connect({ url: server.url.replace('http', 'ws'), room, name: 'f' })
    await follower.waitFor(() => follower.runner.sim !== null, 'the sync')

    // Refusals, each naming what is wrong, with the seq echoed.
    const bad = await errorFor(player, player.gameCommand('openScene', { id: 'nope' }))
    expect([bad.code, bad.reason]).toEqual([
      'invalid',
      'openScene refused: id must be a saved scene id (16 hex digits)',
    ])
    const extra = await errorFor(player, player.gameCommand('openScene', { id, at: 1 }))
    expect(extra.reason).toBe('openScene refused: at is not allowed')
    const unknown = await errorFor(player, player.gameCommand('openScene', { id: 'ffffffffffffffff' }))
    expect([unknown.code, unknown.reason]).toEqual([
      'refused',
      'no saved scene ffffffffffffffff on this server',
    ])
    const pile = createWorld()
    buildBlueprint(pile, pileScene(250))
    const big = (await (await post(sceneText(saveScene(pile)))).json()) as { id: string }
    const tooMany = await errorFor(player, player.gameCommand('openScene', { id: big.id }))
    expect(tooMany.reason).toBe(`scene ${big.id} has 253 bodies; this room holds at most 200`)

    // Paused, so the opened world does not step before it is saved.
    player.command({ k: 'pause', paused: true })
    await player.waitFor(() => player.mirror.paused, 'the pause')
    player.gameCommand('openScene', { id })
    await player.waitFor(() => player.mirror.scene === `file:${id}`, 'the opened scene')
    const file = parseScene(text)
    if (!file.ok) throw new Error(file.error)
    expect(player.mirror.bodies.size).toBe(file.scene.bodies.length)
    // Every body where the file puts it (the wire quantizes positions to 1 mm).
    const bodies = [...player.mirror.bodies.values()].sort((a, b) => a.id - b.id)
    bodies.forEach((b, i) => {
      expect(Math.abs(b.x - file.scene.bodies[i].position.x)).toBeLessThanOrEqual(0.0005)
      expect(Math.abs(b.y - file.scene.bodies[i].position.y)).toBeLessThanOrEqual(0.0005)
    })

    const saveSeq = player.gameCommand('saveScene', {})
    let saved: Extract<ServerMessage, { t: 'scene' }> | undefined
    await player.waitFor(() => {
      saved = player.received.find((m): m is Extract<ServerMessage, { t: 'scene' }> => m.t === 'scene')
      return saved !== undefined
    }, 'the saved scene id')
    expect(saved?.seq).toBe(saveSeq)
    expect(Object.keys(saved ?? {}).sort()).toEqual(documentedFields().get('scene')?.all.sort())
    // Every body in the colour the file gives it (a scene file keeps colours: docs/scene-format.md).
    const drawn = bodies.map((b) => cssColor(b.color))
    expect(drawn).toEqual(file.scene.bodies.map((b) => b.color ?? null))
    expect(drawn.filter((c) => c !== null).length).toBeGreaterThan(3)
    // Opened and saved again: the very file uploaded (colours too), so the very same id.
    expect(saved?.id).toBe(id)
    expect(await (await http(`/scenes/${id}`)).text()).toBe(text)
    const again = await errorFor(player, player.gameCommand('saveScene', {}))
    expect(again.reason).toBe('scene saves are limited to one per second per room')

    // The lockstep client resynced to the opened world and agrees with every later checkpoint.
    player.command({ k: 'pause', paused: false })
    await follower.waitFor(
      () => follower.runner.sim?.scene === `file:${id}`,
      'the follower on the opened scene',
    )
    const checked = follower.runner.stats.hashesChecked
    await follower.waitFor(() => follower.runner.stats.hashesChecked >= checked + 2, 'two more checkpoints')
    expect(follower.runner.stats.desyncs, follower.runner.lastProblem).toBe(0)
    await Promise.all([player.close(), follower.close()])

    // The server keeps at most --max-saved-scenes files (3 here: the two above and the pile): one
    // more makes room by removing the one used longest ago (scene-store-limits.test.ts has the rule).
    const sceneDir = server.config.sceneDir
    expect((await readdir(sceneDir)).filter((f) => f.endsWith('.json')).length).toBe(3)
    const full = await post(machinesText('one more'))
    expect(full.status).toBe(201)
    expect((await readdir(sceneDir)).filter((f) => f.endsWith('.json')).length).toBe(3)

    // The room's log replays with every hash matching, across the scene load.
    await server.close()
    const names = (await readdir(replayDir)).filter((n) => n.startsWith(`${room}-`))
    expect(names.length).toBeGreaterThan(0)
    const report = await replayLog(new Uint8Array(await readFile(join(replayDir, names[0]))), {
      verify: true,
    })
    expect(report.divergence).toBeNull()
    expect(report.hashesChecked).toBeGreaterThanOrEqual(2)
  })
})
