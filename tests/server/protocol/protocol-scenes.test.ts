/*
 * PROTOCOL.md's Scenes table checked against a real server: loading each scene of rules.scenes
 * (in the table's order) with a client built from the document alone gives a `state` whose
 * bodies and joints match the table's counts, with the documented gravity and ground.
 */
import { readFileSync } from 'node:fs'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import type { RunningServer } from '../../../server/server.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'
import { type Decoded, DocClient } from './doc-client.ts'

let server: RunningServer

beforeAll(async () => {
  server = await startTestServer({ defaultScene: 'empty' })
})
afterAll(async () => {
  await server.close()
})

/** Rows of PROTOCOL.md's Scenes table: name, static count, [box, circle, polygon], joints by kind. */
function documentedScenes(doc: string): Array<{
  name: string
  statics: number
  dynamic: number[]
  joints: Record<string, number>
}> {
  const section = doc.slice(doc.indexOf('### Scenes'), doc.indexOf('### Close codes'))
  const rows = []
  for (const line of section.split('\n')) {
    const m = /^\| `([\w-]+)` \|[^|]*\| (\d+) \| (\d+)\/(\d+)\/(\d+) \| ([^|]*) \|$/.exec(line)
    if (!m) continue
    const joints: Record<string, number> = {}
    for (const part of m[6].split(',')) {
      const j = /(\d+) (\w+)/.exec(part)
      if (j) joints[j[2]] = Number(j[1])
    }
    rows.push({ name: m[1], statics: Number(m[2]), dynamic: [m[3], m[4], m[5]].map(Number), joints })
  }
  return rows
}

/** A decoded `state`'s contents in the Scenes table's terms. */
function sceneContents(state: Decoded['state']): {
  statics: number
  dynamic: number[]
  joints: Record<string, number>
} {
  const s = state as {
    bodies: Array<{ kind: number; shapes: Array<{ type: string }> }>
    joints: Array<{ kind: string }>
  }
  const types = ['box', 'circle', 'polygon']
  const joints: Record<string, number> = {}
  for (const j of s.joints) joints[j.kind] = (joints[j.kind] ?? 0) + 1
  return {
    statics: s.bodies.filter((b) => b.kind === 0).length,
    dynamic: types.map((t) => s.bodies.filter((b) => b.kind === 2 && b.shapes[0].type === t).length),
    joints,
  }
}

describe('PROTOCOL.md scenes', { timeout: 60_000 }, () => {
  it("lists the scenes of rules.scenes in order, with the bodies and joints each one's state holds", async () => {
    const table = documentedScenes(readFileSync('shared/protocol/PROTOCOL.md', 'utf8'))
    const c = await DocClient.joined(server.url, 'scenes', 'loader')
    expect(table.map((r) => r.name)).toEqual((c.first('welcome').rules as { scenes: string[] }).scenes)
    let seq = 0
    let lastLoad = 0
    for (const row of table) {
      let state: Decoded | undefined
      while (!state) {
        const s = ++seq
        const from = c.messages.length
        c.send({ t: 'input', seq: s, cmd: { k: 'scene', name: row.name } })
        const reply = (): Decoded | undefined =>
          c.messages
            .slice(from)
            .find(
              (m) =>
                (m.t === 'state' && (m.state as { scene: string }).scene === row.name) ||
                (m.t === 'error' && m.seq === s),
            )
        await until(() => reply() !== undefined, `the ${row.name} scene`)
        const m = reply()!
        if (m.t === 'state') state = m
        // Loads are limited to one per 10 ticks: retry once the room is past that.
        else await c.waitFor((x) => x.t === 'snap' && (x.tick as number) > lastLoad + 10, 'ten ticks')
      }
      lastLoad = (state.state as { tick: number }).tick
      const contents = sceneContents(state.state)
      expect(contents, row.name).toEqual({ statics: row.statics, dynamic: row.dynamic, joints: row.joints })
      const s = state.state as { gravity: number[]; bodies: Array<Record<string, unknown>> }
      expect(s.gravity, row.name).toEqual([0, -10])
      // The ground: the lowest id, static, 200 m wide, its top at y = 0.
      const ground = s.bodies.reduce((lo, b) => ((b.id as number) < (lo.id as number) ? b : lo))
      expect(ground, row.name).toMatchObject({ kind: 0, y: -1000, shapes: [{ type: 'box', hw: 100, hh: 1 }] })
    }
    c.end()
  })
})
