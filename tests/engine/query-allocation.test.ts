/*
 * The per-tick queries allocate nothing once warm: ray casts against every shape kind, a shape
 * cast and a closest-hit TreeRayCast through a 1,000-leaf tree, the WorldQueries, and the World's
 * own query methods in their reusing forms (query-allocation-scene.ts), with
 * reused inputs and outputs, measured in a separate quiet process as the engine's step is
 * (tests/support/measure-allocation.ts): heap growth with no collection in between.
 */
import { dirname } from 'node:path'
import { fileURLToPath } from 'node:url'
import { describe, expect, it } from 'vitest'
import { measureAllocation } from '../support/measure-allocation.ts'

/** Bytes per block of queries above which the block counts as allocating (one small object is 32-64). */
const BOUND = 16

describe('query allocation', () => {
  it('ray casts, a shape cast and a tree ray cast allocate nothing once warm', async () => {
    const result = await measureAllocation({
      resolveDir: dirname(fileURLToPath(import.meta.url)),
      setup: `
import { QueryScene } from './query-allocation-scene.ts'
const scene = new QueryScene()
`,
      unit: 'scene.unit()',
      units: 20000,
      warmup: 20000,
      rounds: 3,
      facts: '{ hits: scene.hits }',
      reportAbove: BOUND,
    })
    console.log(
      `query allocation: ${result.gcCount} collections, heap growth ${result.heapGrowth} bytes over ${result.units} blocks, ${result.facts.hits} hits` +
        (result.allocators.length ? `; allocating: ${JSON.stringify(result.allocators)}` : ''),
    )
    expect(result.facts.hits).toBeGreaterThan(40000)
    expect(result.gcCount, JSON.stringify(result.allocators)).toBe(0)
    expect(result.heapGrowth / result.units, JSON.stringify(result.allocators)).toBeLessThan(BOUND)
  })

  it('the world queries (closest and all-hits rays, shape cast, AABB, point and shape overlaps) allocate nothing once warm', async () => {
    const result = await measureAllocation({
      resolveDir: dirname(fileURLToPath(import.meta.url)),
      setup: `
import { QueryScene } from './query-allocation-scene.ts'
const scene = new QueryScene()
`,
      unit: 'scene.worldUnit()',
      units: 10000,
      warmup: 10000,
      rounds: 3,
      facts: '{ hits: scene.hits }',
      reportAbove: BOUND,
    })
    console.log(
      `world query allocation: ${result.gcCount} collections, heap growth ${result.heapGrowth} bytes over ${result.units} blocks, ${result.facts.hits} hits` +
        (result.allocators.length ? `; allocating: ${JSON.stringify(result.allocators)}` : ''),
    )
    expect(result.facts.hits).toBeGreaterThan(40000)
    expect(result.gcCount, JSON.stringify(result.allocators)).toBe(0)
    expect(result.heapGrowth / result.units, JSON.stringify(result.allocators)).toBeLessThan(BOUND)
  })

  it("the World's query methods in their reusing forms (out, ...Into) allocate nothing once warm", async () => {
    const result = await measureAllocation({
      resolveDir: dirname(fileURLToPath(import.meta.url)),
      setup: `
import { WorldApiScene } from './query-allocation-scene.ts'
const scene = new WorldApiScene()
`,
      unit: 'scene.unit()',
      units: 10000,
      warmup: 10000,
      rounds: 3,
      facts: '{ hits: scene.hits }',
      reportAbove: BOUND,
    })
    console.log(
      `World query allocation: ${result.gcCount} collections, heap growth ${result.heapGrowth} bytes over ${result.units} blocks, ${result.facts.hits} hits` +
        (result.allocators.length ? `; allocating: ${JSON.stringify(result.allocators)}` : ''),
    )
    expect(result.facts.hits).toBeGreaterThan(40000)
    expect(result.gcCount, JSON.stringify(result.allocators)).toBe(0)
    expect(result.heapGrowth / result.units, JSON.stringify(result.allocators)).toBeLessThan(BOUND)
  })
})
