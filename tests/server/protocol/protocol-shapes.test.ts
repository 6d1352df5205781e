/*
 * PROTOCOL.md's Shape, Body and `spawn` promises, against a real server with a client built from
 * the document alone (doc-client.ts: `ws` and @msgpack/msgpack, no shared/ code). Expected values
 * are worked by hand from the document: vertex lists of offset boxes, compound masses from areas
 * times densities (closed forms), the L outline's shoelace area, default settings left out, the
 * spawner's colour taken from the roster's '#rrggbb'.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { decompose } from '../../../engine/index.ts'
import type { RunningServer } from '../../../server/server.ts'
import { startTestServer } from '../../support/test-server.ts'
import { type Decoded, DocClient } from './doc-client.ts'

let server: RunningServer

beforeAll(async () => {
  server = await startTestServer({ defaultScene: 'empty', heartbeatMs: 60_000, maxRejects: 100 })
})
afterAll(async () => {
  await server.close()
})

type Body = Record<string, unknown> & { id: number; seq?: number; shapes: Array<Record<string, unknown>> }

const added = (c: DocClient): Body[] => c.all('events').flatMap((e) => e.add as Body[])

/** The answer to the input with `seq`: the body it added, or its error. */
async function answer(c: DocClient, seq: number): Promise<Body | Decoded> {
  await c.waitFor(
    () => added(c).some((b) => b.seq === seq) || c.all('error').some((e) => e.seq === seq),
    `answer to ${seq}`,
  )
  return added(c).find((b) => b.seq === seq) ?? c.all('error').find((e) => e.seq === seq)!
}

/** Every number in a value (recursively). */
function numbers(v: unknown, out: number[] = []): number[] {
  if (typeof v === 'number') out.push(v)
  else if (Array.isArray(v)) for (const x of v) numbers(x, out)
  else if (v && typeof v === 'object' && !(v instanceof Uint8Array))
    for (const x of Object.values(v)) numbers(x, out)
  return out
}

/** Shoelace area of a flat [x0, y0, ...] polygon (m^2, positive counter-clockwise). */
function area(v: readonly number[]): number {
  let twice = 0
  for (let i = 0; i < v.length; i += 2) {
    const j = (i + 2) % v.length
    twice += v[i] * v[j + 1] - v[j] * v[i + 1]
  }
  return twice / 2
}

describe('PROTOCOL.md Shape, Body and spawn', { timeout: 30_000 }, () => {
  it('a compound spawn travels with every kind, its placements and only its non-default settings, in the spawner colour', async () => {
    const c = await DocClient.joined(server.url, 'kinds', 'maker')
    const shapes = [
      { type: 'box', hw: 0.5, hh: 0.25, x: 1, y: 0.5 },
      { type: 'circle', radius: 0.3, x: -1, y: 0, density: 2, friction: 0.6 },
      { type: 'capsule', v: [-0.5, -0.5, 0.5, -0.5], radius: 0.2, friction: 0.2, restitution: 0.5 },
      { type: 'polygon', v: [0, 1, 1, 1, 0.5, 2], radius: 0.1, rolling: 0.3, tangent: -2 },
      { type: 'segment', v: [-1, 2, 1, 2], filter: [2, 5, -3], sensor: true },
      { type: 'box', hw: 0.2, hh: 0.2, filter: [1, 4294967295, 0], sensor: false },
    ]
    c.send({ t: 'input', seq: 1, cmd: { k: 'spawn', shapes, x: 0, y: 20 } })
    const body = (await answer(c, 1)) as Body
    expect(body.kind).toBe(2)
    expect(body.shapes).toEqual([
      // An offset box travels as its polygon, counter-clockwise from its (-hw, -hh) corner.
      { type: 'polygon', v: [0.5, 0.25, 1.5, 0.25, 1.5, 0.75, 0.5, 0.75] },
      // friction 0.6 is the default: left out.
      { type: 'circle', radius: 0.3, x: -1, y: 0, density: 2 },
      { type: 'capsule', v: [-0.5, -0.5, 0.5, -0.5], radius: 0.2, friction: 0.2, restitution: 0.5 },
      // (0, 1), (1, 1), (0.5, 2) is counter-clockwise already: kept as given.
      { type: 'polygon', v: [0, 1, 1, 1, 0.5, 2], radius: 0.1, rolling: 0.3, tangent: -2 },
      { type: 'segment', v: [-1, 2, 1, 2], filter: [2, 5, -3], sensor: true },
      // The default filter and sensor: false are left out.
      { type: 'box', hw: 0.2, hh: 0.2 },
    ])
    const me = (c.first('welcome').players as Array<{ id: number; color: string }>).find(
      (p) => p.id === c.id,
    )!
    expect(body.color).toBe(Number.parseInt(me.color.slice(1), 16))
    // A late joiner's full state lists the same body the same way.
    const late = await DocClient.joined(server.url, 'kinds', 'late')
    const state = late.first('welcome').state as { bodies: Body[] }
    const again = state.bodies.find((b) => b.id === body.id)!
    expect(again.shapes).toEqual(body.shapes)
    expect(again.color).toBe(body.color)
    expect(numbers(state).every(Number.isFinite)).toBe(true)
    expect(numbers(c.all('events')).every(Number.isFinite)).toBe(true)
    c.end()
    late.end()
  })

  it('a compound body weighs the sum of its shapes (areas times densities), as the contacts message reports', async () => {
    const c = await DocClient.joined(server.url, 'mass', 'weigher')
    const shapes = [
      { type: 'box', hw: 0.5, hh: 0.5, density: 2 },
      { type: 'circle', radius: 0.5, x: 2, y: 0 },
      { type: 'capsule', v: [0, 1, 1, 1], radius: 0.25, density: 4 },
    ]
    c.send({ t: 'input', seq: 1, cmd: { k: 'spawn', shapes, x: 0, y: 3 } })
    const body = (await answer(c, 1)) as Body
    c.send({ t: 'input', seq: 2, cmd: { k: 'inspect', body: body.id } })
    const contacts = await c.waitFor((m) => m.t === 'contacts' && m.body === body.id, 'contacts')
    // Box 1 m^2 x 2, disc pi/4 x 1, capsule (1 x 0.5 + pi/16) x 4.
    const mass = 2 + Math.PI / 4 + 4 * (0.5 + Math.PI / 16)
    expect(contacts.mass as number).toBeCloseTo(mass, 9)
    c.end()
  })

  it('an outline is decomposed by the room into convex pieces that cover its area; a static spawn stays put and may be deleted', async () => {
    const c = await DocClient.joined(server.url, 'outline', 'drawer')
    // An L: 2 x 2 with the top-right 1 x 1 cut away (area 3), given clockwise.
    const outline = [0, 0, 0, 2, 1, 2, 1, 1, 2, 1, 2, 0]
    c.send({ t: 'input', seq: 1, cmd: { k: 'spawn', outline, x: -5, y: 5, friction: 0.3 } })
    const body = (await answer(c, 1)) as Body
    expect(body.shapes.length).toBeGreaterThanOrEqual(2)
    let total = 0
    for (const s of body.shapes) {
      expect(s.type).toBe('polygon')
      expect(s.friction).toBe(0.3)
      const v = s.v as number[]
      expect(area(v)).toBeGreaterThan(0) // counter-clockwise
      // Convex: every turn is to the left.
      for (let i = 0; i < v.length; i += 2) {
        const [ax, ay, bx, by] = [v[i], v[i + 1], v[(i + 2) % v.length], v[(i + 3) % v.length]]
        const [cx, cy] = [v[(i + 4) % v.length], v[(i + 5) % v.length]]
        expect((bx - ax) * (cy - by) - (by - ay) * (cx - bx)).toBeGreaterThan(0)
      }
      total += area(v)
    }
    expect(total).toBeCloseTo(3, 12)
    // Static, in a colour of its own: listed as kind 0 at its place, never in snapshots.
    const ground = [-3, 0, 3, 0]
    c.send({
      t: 'input',
      seq: 2,
      cmd: { k: 'spawn', shape: { type: 'segment', v: ground }, x: 0, y: 8, static: true, color: 0x123456 },
    })
    const line = (await answer(c, 2)) as Body
    expect(line).toMatchObject({ kind: 0, x: 0, y: 8000, a: 0, color: 0x123456 })
    // Another player deletes it; the scene's ground (body 1) stays refused.
    const other = await DocClient.joined(server.url, 'outline', 'cleaner')
    other.send({ t: 'input', seq: 7, cmd: { k: 'delete', body: line.id } })
    other.send({ t: 'input', seq: 8, cmd: { k: 'delete', body: 1 } })
    await other.waitFor(
      () => other.all('events').some((e) => (e.remove as number[]).includes(line.id)),
      'removed',
    )
    const refusal = await other.waitFor((m) => m.t === 'error' && m.seq === 8, 'ground refused')
    expect(refusal).toMatchObject({ code: 'refused', reason: 'body 1 does not exist or is static' })
    c.end()
    other.end()
  })

  it('refuses bad shapes with errors naming the field (invalid), and what the engine refuses with its own reason (refused)', async () => {
    const c = await DocClient.joined(server.url, 'refusals', 'breaker')
    const many = Array.from({ length: 17 }, (_, i) => ({ type: 'circle', radius: 0.1, x: i * 0.5 - 4, y: 0 }))
    const bowtie = [0, 0, 2, 2, 2, 0, 0, 2]
    let engineReason = ''
    try {
      decompose([
        { x: 0, y: 0 },
        { x: 2, y: 2 },
        { x: 2, y: 0 },
        { x: 0, y: 2 },
      ])
    } catch (e) {
      engineReason = (e as Error).message
    }
    expect(engineReason).toMatch(/cross|intersect/)
    const cases: Array<[Record<string, unknown>, string, string | RegExp]> = [
      [{ shapes: [] }, 'invalid', 'shapes must be a list of 1 to 16 shapes'],
      [{ shapes: many }, 'invalid', 'shapes must be a list of 1 to 16 shapes'],
      [{ shape: { type: 'capsule', v: [0, 0, 1, 0] } }, 'invalid', 'capsule is missing field "radius"'],
      [
        {
          shapes: [
            { type: 'circle', radius: 1 },
            { type: 'capsule', v: [0, 0, 1], radius: 0.1 },
          ],
        },
        'invalid',
        'shapes[1] capsule v must be a flat list of 2 points [x0, y0, x1, y1, ...]',
      ],
      [
        { shape: { type: 'polygon', v: [0, 0, 1, 0, 2, 1, 2, 2, 1, 3, 0, 3, -1, 2, -1, 1, -0.5, 0.5] } },
        'invalid',
        'polygon v must be a flat list of 3 to 8 points [x0, y0, x1, y1, ...]',
      ],
      [
        { shape: { type: 'circle', radius: 1, x: 10.5 } },
        'invalid',
        'circle x must be a finite number in [-10, 10]',
      ],
      [
        { shape: { type: 'polygon', v: [0, 0, 1, 0, 0, 1], radius: 0.01 } },
        'invalid',
        'polygon radius must be a finite number in [0.05, 10]',
      ],
      [
        { shape: { type: 'box', hw: 1, hh: 1, filter: [1, 2] } },
        'invalid',
        'shape filter must be [categoryBits, maskBits, groupIndex]',
      ],
      [
        { shape: { type: 'box', hw: 1, hh: 1, filter: [1, 2 ** 32, 0] } },
        'invalid',
        'shape filter maskBits must be an integer in [0, 4294967295]',
      ],
      [
        { shape: { type: 'box', hw: 1, hh: 1, rolling: 11 } },
        'invalid',
        'shape rolling must be a finite number in [0, 10]',
      ],
      [
        { shapes: [{ type: 'box', hw: 1, hh: 1, tangent: -101 }] },
        'invalid',
        'shapes[0] tangent must be a finite number in [-100, 100]',
      ],
      [
        { shape: { type: 'box', hw: 1, hh: 1, sensor: 'yes' } },
        'invalid',
        'shape sensor must be true or false',
      ],
      [{ shape: { type: 'box', hw: 1, hh: 1, glue: 1 } }, 'invalid', 'shape has unknown field "glue"'],
      [
        { shape: { type: 'blob' } },
        'invalid',
        'shape type must be "circle", "box", "polygon", "capsule", "segment" or "chain"',
      ],
      [
        { shape: { type: 'box', hw: 1, hh: 1 }, color: 0x1000000 },
        'invalid',
        'color must be an integer in [0, 16777215]',
      ],
      [{ shape: { type: 'box', hw: 1, hh: 1 }, static: 1 }, 'invalid', 'static must be true or false'],
      [
        { outline: new Array(130).fill(0) },
        'invalid',
        'outline must be a flat list of 3 to 64 points [x0, y0, x1, y1, ...]',
      ],
      [
        { outline: [0, 0, 1, 0, 0, 1], shape: { type: 'box', hw: 1, hh: 1 } },
        'invalid',
        'spawn needs exactly one of shape, shapes or outline',
      ],
      [{}, 'invalid', 'spawn needs exactly one of shape, shapes or outline'],
      [{ outline: bowtie }, 'refused', `spawn refused: ${engineReason}`],
      [
        { shape: { type: 'segment', v: [0, 0, 1, 0] } },
        'refused',
        /^spawn refused: a dynamic body needs a shape with mass/,
      ],
      [
        { shape: { type: 'capsule', v: [0, 0, 0.0005, 0], radius: 0.1 } },
        'refused',
        /^spawn refused: capsule points .* are closer than/,
      ],
      [
        { shape: { type: 'chain', v: [1, 0, 0, 0, -1, 0] }, static: true },
        'invalid',
        'chain v must be a flat list of 4 to 64 points [x0, y0, x1, y1, ...]',
      ],
      [
        { shape: { type: 'chain', v: [2, 0, 1, 0, -1, 0, -2, 0] } },
        'refused',
        /^spawn refused: chain shapes are for static bodies only/,
      ],
    ]
    cases.forEach(([extra, ,], i) => {
      c.send({ t: 'input', seq: 100 + i, cmd: { k: 'spawn', x: 3 * i - 30, y: 10, ...extra } })
    })
    for (const [i, [, code, reason]] of cases.entries()) {
      const got = await answer(c, 100 + i)
      expect(got.t, `case ${i}`).toBe('error')
      expect(got.code, `case ${i}`).toBe(code)
      if (typeof reason === 'string') expect(got.reason, `case ${i}`).toBe(reason)
      else expect(got.reason, `case ${i}`).toMatch(reason)
    }
    // A static segment is fine: it needs no mass.
    c.send({
      t: 'input',
      seq: 300,
      cmd: { k: 'spawn', shape: { type: 'segment', v: [0, 0, 1, 0] }, x: 0, y: 1, static: true },
    })
    expect(await answer(c, 300)).toMatchObject({ kind: 0, shapes: [{ type: 'segment', v: [0, 0, 1, 0] }] })
    c.end()
  })
})
