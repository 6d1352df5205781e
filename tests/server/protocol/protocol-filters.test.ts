/*
 * PROTOCOL.md's Shape `filter` on bodies, against a real server with the document-only client
 * (doc-client.ts: `ws` and @msgpack/msgpack, no shared/ code): a goal room's welcome lists each
 * goal-line gate's shape with `filter: [categoryBits, maskBits, groupIndex]` = [8, 2, 0] (docs/
 * games.md, Goal: a gate only discs, category 2, collide with), the goal sensors with `sensor:
 * true`, and the plain walls without a filter (the default [1, 0xffffffff, 0] is left out). The
 * page's renderer reads just these fields: shapeStyle makes the gates 'gate', the goals 'sensor' and
 * the walls 'solid'.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { shapeStyle } from '../../../client/draw/renderer.ts'
import type { RunningServer } from '../../../server/server.ts'
import type { WireShape } from '../../../shared/index.ts'
import { startTestServer } from '../../support/test-server.ts'
import { DocClient } from './doc-client.ts'

let server: RunningServer

beforeAll(async () => {
  server = await startTestServer({ heartbeatMs: 60_000 })
})
afterAll(async () => {
  await server.close()
})

type Body = { id: number; kind: number; shapes: Array<Record<string, unknown>> }

describe('collision filters on the wire', () => {
  it("a goal room's gates carry their filter, its goals sensor: true, its walls neither", async () => {
    const c = await DocClient.open(server.url, 'filters')
    c.send({ t: 'join', v: 3, room: '', name: 'f', mode: 'snapshot', game: 'goal' })
    const welcome = await c.waitFor((m) => m.t === 'welcome', 'welcome')
    const bodies = (welcome.state as { bodies: Body[] }).bodies
    const statics = bodies.filter((b) => b.kind === 0)
    const shapes = statics.flatMap((b) => b.shapes)
    const gates = shapes.filter((s) => s.filter !== undefined)
    expect(gates.length).toBe(2)
    for (const g of gates) expect(g.filter).toEqual([8, 2, 0])
    const sensors = shapes.filter((s) => s.sensor === true)
    expect(sensors.length).toBe(2)
    for (const s of sensors) expect(s.filter).toBeUndefined()
    const walls = shapes.filter((s) => s.filter === undefined && s.sensor === undefined)
    expect(walls.length).toBeGreaterThan(0)

    const styles = (list: Array<Record<string, unknown>>) =>
      list.map((s) => shapeStyle(0, s as unknown as WireShape))
    expect(styles(gates)).toEqual(['gate', 'gate'])
    expect(styles(sensors)).toEqual(['sensor', 'sensor'])
    expect(new Set(styles(walls))).toEqual(new Set(['solid']))
    c.ws.close()
  })
})
