/*
 * The saved-scene store's bounds against a real server (docs/scene-format.md, "Kept on the
 * server"; issue 31): at most --max-saved-scenes files and --max-saved-scene-bytes bytes; a save
 * that would pass either removes the scenes used longest ago first (a fetch and an openScene count
 * as a use); a scene larger than the byte bound alone is refused and removes nothing. The oracle is
 * a plain list model of the documented rule, kept by this test, and the directory itself.
 */
import { mkdtemp, readdir, stat } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { box, createWorld } from '../../../engine/index.ts'
import { saveScene, sceneText } from '../../../games/index.ts'
import type { RunningServer } from '../../../server/server.ts'
import { startTestServer } from '../../support/test-server.ts'

const MAX_SCENES = 4
const MAX_BYTES = 100_000
let server: RunningServer
let dir: string

beforeAll(async () => {
  dir = await mkdtemp(join(tmpdir(), 'concord-scene-limits-'))
  server = await startTestServer({ sceneDir: dir, maxSavedScenes: MAX_SCENES, maxSavedSceneBytes: MAX_BYTES })
})
afterAll(async () => {
  await server?.close()
})

/** A scene file of `boxes` boxes (its size grows with them), named `name`. */
function sceneOf(name: string, boxes: number): string {
  const world = createWorld()
  world.createBody({ type: 'static', position: { x: 0, y: -0.5 }, shape: box(50, 0.5) })
  for (let i = 0; i < boxes; i++)
    world.createBody({
      type: 'dynamic',
      position: { x: (i % 40) - 20, y: 1 + Math.floor(i / 40) },
      shape: box(0.4, 0.4),
    })
  return sceneText(saveScene(world, { name }))
}

const post = (text: string) => fetch(`${server.url}/scenes`, { method: 'POST', body: text })
const get = (id: string) => fetch(`${server.url}/scenes/${id}`)

/** The kept files: ids and total bytes. */
async function kept(): Promise<{ ids: string[]; bytes: number }> {
  const names = (await readdir(dir)).filter((f) => /^[0-9a-f]{16}\.json$/.test(f))
  let bytes = 0
  for (const n of names) bytes += (await stat(join(dir, n))).size
  return { ids: names.map((n) => n.slice(0, 16)).sort(), bytes }
}

/** The documented rule as a list, least recently used first. */
class Model {
  used: Array<{ id: string; bytes: number }> = []
  use(id: string): void {
    const i = this.used.findIndex((s) => s.id === id)
    this.used.push(...this.used.splice(i, 1))
  }
  save(id: string, bytes: number): void {
    if (this.used.some((s) => s.id === id)) {
      this.use(id)
      return
    }
    const total = () => this.used.reduce((sum, s) => sum + s.bytes, 0)
    while (this.used.length + 1 > MAX_SCENES || total() + bytes > MAX_BYTES) this.used.shift()
    this.used.push({ id, bytes })
  }
  ids(): string[] {
    return this.used.map((s) => s.id).sort()
  }
}

describe('saved scenes are bounded by count and bytes', { timeout: 60_000 }, () => {
  it('removes the scenes used longest ago to make room, and refuses one larger than the bound', async () => {
    const model = new Model()
    const ids: string[] = []
    const save = async (text: string): Promise<string> => {
      const res = await post(text)
      expect(res.status, await res.clone().text()).toBe(201)
      const { id } = (await res.json()) as { id: string }
      model.save(id, Buffer.byteLength(text))
      return id
    }
    // Four small scenes fill the count (each a few KB: far below the byte bound).
    for (let i = 0; i < MAX_SCENES; i++) ids.push(await save(sceneOf(`small ${i}`, 5 + i)))
    expect((await kept()).ids).toEqual(model.ids())
    // Using the oldest (a fetch) keeps it; the next save removes the second oldest instead.
    expect((await get(ids[0])).status).toBe(200)
    model.use(ids[0])
    const fifth = await save(sceneOf('small 4', 9))
    expect((await kept()).ids).toEqual(model.ids())
    expect(model.ids()).not.toContain(ids[1])
    expect((await kept()).ids).toContain(ids[0])
    const gone = await get(ids[1])
    expect([gone.status, await gone.text()]).toEqual([404, `no saved scene ${ids[1]} on this server\n`])
    // Opening a scene in a room is a use too.
    const bot = await BotClient.connect({ url: server.url, room: 'limits', name: 'a' })
    bot.gameCommand('openScene', { id: ids[2] })
    await bot.waitFor(() => bot.mirror.scene === `file:${ids[2]}`, 'the opened scene')
    model.use(ids[2])
    await bot.close()
    // A big scene (about half the byte bound) passes the bytes: as many of the oldest go as needed.
    const big = sceneOf('big', 200)
    expect(Buffer.byteLength(big)).toBeGreaterThan(MAX_BYTES / 3)
    await save(big)
    let now = await kept()
    expect(now.ids).toEqual(model.ids())
    expect(now.bytes).toBeLessThanOrEqual(MAX_BYTES)
    // A fetch of the fifth makes it the newest; a second big scene then removes the oldest ones,
    // the first big scene among them when the bytes still do not fit.
    expect((await get(fifth)).status).toBe(200)
    model.use(fifth)
    await save(sceneOf('big 2', 210))
    now = await kept()
    expect(now.ids).toEqual(model.ids())
    expect(now.bytes).toBeLessThanOrEqual(MAX_BYTES)
    // The bytes, not the count, removed the second of the two: three scenes are left.
    expect(now.ids.length).toBe(MAX_SCENES - 1)
    // Larger than the bound by itself: refused, naming both sizes, and nothing is removed.
    const huge = sceneOf('huge', 500)
    const size = Buffer.byteLength(huge)
    expect(size).toBeGreaterThan(MAX_BYTES)
    const refused = await post(huge)
    expect([refused.status, await refused.text()]).toEqual([
      507,
      `this server keeps at most ${MAX_BYTES} bytes of saved scenes; this one has ${size}\n`,
    ])
    expect(await kept()).toEqual(now)
    // Saving a kept scene again keeps one file and counts as a use.
    const again = await save(sceneOf('big 2', 210))
    expect((await kept()).ids).toEqual(model.ids())
    expect(model.used.at(-1)?.id).toBe(again)
  })
})
