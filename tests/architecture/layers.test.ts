/*
 * The layers, checked on the source text of every product file (DESIGN.md "The layout"):
 *
 * - Which layer may import which: engine -> nothing; shared -> engine; games -> engine, shared;
 *   server, client, bots -> engine, shared, games; bench -> all of those (engine internals only
 *   through engine/internal.ts) and the tooling it shares with the tests (tests/support/, the build
 *   scripts in scripts/). Server never imports client; client never imports server or bench.
 *   The client SDK: sdk -> engine, shared, games, client; nothing imports sdk.
 *   Tests and build scripts may import anything.
 * - Outside a layer, only its index.ts (and engine/internal.ts, for bench alone).
 * - Inside a layer, an import that leaves a concept folder (server/rooms/, engine/joints/, ...)
 *   goes through that folder's index.ts; shared's parts depend one way: protocol <- sim <- replay.
 * - Every folder of a layer has an index.ts.
 * - No value import cycle anywhere (type-only cycles are erased at compile time and allowed).
 *
 * The checker is a pure function over (path -> source), tested on small fixtures first so that a
 * broken rule cannot pass silently; then it runs over the repository.
 */
import { execFileSync } from 'node:child_process'
import { existsSync, readFileSync, statSync } from 'node:fs'
import { posix } from 'node:path'
import { describe, expect, it } from 'vitest'
import { importStatements } from '../support/source-scan.ts'

const PRODUCT = ['engine', 'shared', 'games', 'server', 'client', 'bots', 'sdk'] as const
const LAYERS = [...PRODUCT, 'bench'] as const
type Layer = (typeof LAYERS)[number]

/** The layers each layer may import (besides itself). */
const ALLOWED: Record<Layer, readonly Layer[]> = {
  engine: [],
  shared: ['engine'],
  games: ['engine', 'shared'],
  server: ['engine', 'shared', 'games'],
  client: ['engine', 'shared', 'games'],
  bots: ['engine', 'shared', 'games'],
  // The client SDK (docs/sdk.md) wraps the client's pieces; nothing imports it.
  sdk: ['engine', 'shared', 'games', 'client'],
  bench: ['engine', 'shared', 'games', 'server', 'client', 'bots'],
}

/** What bench may import outside the layers: the test harness and the build scripts it shares. */
const BENCH_TOOLING = ['tests/support/', 'scripts/']

/** shared's parts, in dependency order: a part imports only parts before it. */
const SHARED_PARTS = ['protocol', 'sim', 'replay']

const layerOf = (path: string): Layer | null => {
  const top = path.split('/')[0]
  return (LAYERS as readonly string[]).includes(top) ? (top as Layer) : null
}

/** A layer's concept folder of a file (`server/rooms`), or null for files at a layer's root. */
function conceptOf(path: string): string | null {
  const parts = path.split('/')
  return parts.length >= 3 && layerOf(path) !== null ? `${parts[0]}/${parts[1]}` : null
}

/** Every rule broken by the imports of `files` (path -> source), as "file:line: what (rule)". */
function layerViolations(files: ReadonlyMap<string, string>): string[] {
  const found: string[] = []
  for (const [file, src] of files) {
    const from = layerOf(file)
    if (from === null) continue
    for (const { specifier, line } of importStatements(src)) {
      const where = `${file}:${line}`
      if (!specifier.startsWith('.')) {
        if (from === 'engine') found.push(`${where}: imports '${specifier}' (engine imports nothing)`)
        continue
      }
      const target = posix.normalize(posix.join(posix.dirname(file), specifier))
      const to = layerOf(target)
      if (to === from) {
        const fromConcept = conceptOf(file)
        const toConcept = conceptOf(target)
        if (toConcept !== null && toConcept !== fromConcept && target !== `${toConcept}/index.ts`) {
          found.push(
            `${where}: imports ${target} (outside a folder, only its index.ts: ${toConcept}/index.ts)`,
          )
        }
        if (from === 'shared' && fromConcept !== null && toConcept !== null) {
          const a = SHARED_PARTS.indexOf(fromConcept.split('/')[1])
          const b = SHARED_PARTS.indexOf(toConcept.split('/')[1])
          if (b > a)
            found.push(
              `${where}: imports ${target} (shared's parts depend one way: protocol <- sim <- replay)`,
            )
        }
        continue
      }
      if (to === null && from === 'bench' && BENCH_TOOLING.some((prefix) => target.startsWith(prefix)))
        continue
      if (to === null) {
        found.push(`${where}: imports ${target} (a layer imports only layers: ${LAYERS.join(', ')})`)
        continue
      }
      if (!ALLOWED[from].includes(to)) {
        found.push(
          `${where}: imports ${target} (${from} never imports ${to}; ${from} may import ${ALLOWED[from].join(', ') || 'nothing'})`,
        )
        continue
      }
      const entry = target === `${to}/index.ts` || (from === 'bench' && target === 'engine/internal.ts')
      if (!entry) {
        const also = to === 'engine' && from === 'bench' ? ' or engine/internal.ts' : ''
        found.push(`${where}: imports ${target} (outside a layer, only its index.ts: ${to}/index.ts${also})`)
      }
    }
  }
  return found.sort()
}

/** Value import cycles among `files` (Tarjan's strongly connected components), each as a path list. */
function valueCycles(files: ReadonlyMap<string, string>): string[][] {
  const edges = new Map<string, string[]>()
  for (const [file, src] of files) {
    const deps: string[] = []
    for (const s of importStatements(src)) {
      if (s.typeOnly || !s.specifier.startsWith('.')) continue
      const target = posix.normalize(posix.join(posix.dirname(file), s.specifier))
      if (files.has(target)) deps.push(target)
    }
    edges.set(file, deps)
  }
  const index = new Map<string, number>()
  const low = new Map<string, number>()
  const stack: string[] = []
  const onStack = new Set<string>()
  const cycles: string[][] = []
  let next = 0
  const visit = (v: string): void => {
    index.set(v, next)
    low.set(v, next++)
    stack.push(v)
    onStack.add(v)
    for (const w of edges.get(v) ?? []) {
      if (!index.has(w)) {
        visit(w)
        low.set(v, Math.min(low.get(v)!, low.get(w)!))
      } else if (onStack.has(w)) low.set(v, Math.min(low.get(v)!, index.get(w)!))
    }
    if (low.get(v) !== index.get(v)) return
    const component: string[] = []
    let w: string
    do {
      w = stack.pop()!
      onStack.delete(w)
      component.push(w)
    } while (w !== v)
    if (component.length > 1 || (edges.get(v) ?? []).includes(v)) cycles.push(component.sort())
  }
  for (const v of [...edges.keys()].sort()) if (!index.has(v)) visit(v)
  return cycles
}

/** The repository's tracked and new TypeScript and JavaScript module files (not node_modules, not dist). */
function repositoryFiles(): Map<string, string> {
  const listed = execFileSync('git', ['ls-files', '--cached', '--others', '--exclude-standard'], {
    encoding: 'utf8',
  })
  const files = new Map<string, string>()
  for (const path of listed.split('\n')) {
    if (!/\.(ts|mts|mjs)$/.test(path) || path.endsWith('.d.ts') || path.endsWith('.d.mts')) continue
    if (!existsSync(path)) continue
    files.set(path, readFileSync(path, 'utf8'))
  }
  return files
}

describe('the layer checker itself', () => {
  const fixture = (entries: Record<string, string>) => new Map(Object.entries(entries))

  it('names the file, the line and the rule for each kind of violation', () => {
    const found = layerViolations(
      fixture({
        'server/rooms/room.ts': "import { draw } from '../../client/draw/index.ts'\n",
        'client/app.ts':
          "\nimport { startServer } from '../server/index.ts'\nimport { x } from '../bench/stats.ts'\n",
        'server/net/transport.ts':
          "import { Room } from '../rooms/room.ts'\nimport { Room2 } from '../rooms/index.ts'\n",
        'bots/bot.ts': "import { ClientMirror } from '../shared/sim/client-mirror.ts'\n",
        'bench/a.ts':
          "import { BroadPhase } from '../engine/internal.ts'\nimport { World } from '../engine/world/world.ts'\n",
        'client/b.ts': "import { BroadPhase } from '../engine/internal.ts'\n",
        'engine/world/world.ts':
          "import { encode } from 'msgpackr'\nimport { q } from '../../shared/index.ts'\n",
        'shared/protocol/codec.ts': "import type { RoomSimulation } from '../sim/index.ts'\n",
        'shared/sim/a.ts': "import { encode } from '../protocol/index.ts'\n",
      }),
    )
    expect(found).toEqual([
      'bench/a.ts:2: imports engine/world/world.ts (outside a layer, only its index.ts: engine/index.ts or engine/internal.ts)',
      'bots/bot.ts:1: imports shared/sim/client-mirror.ts (outside a layer, only its index.ts: shared/index.ts)',
      'client/app.ts:2: imports server/index.ts (client never imports server; client may import engine, shared, games)',
      'client/app.ts:3: imports bench/stats.ts (client never imports bench; client may import engine, shared, games)',
      'client/b.ts:1: imports engine/internal.ts (outside a layer, only its index.ts: engine/index.ts)',
      "engine/world/world.ts:1: imports 'msgpackr' (engine imports nothing)",
      'engine/world/world.ts:2: imports shared/index.ts (engine never imports shared; engine may import nothing)',
      'server/net/transport.ts:1: imports server/rooms/room.ts (outside a folder, only its index.ts: server/rooms/index.ts)',
      'server/rooms/room.ts:1: imports client/draw/index.ts (server never imports client; server may import engine, shared, games)',
      "shared/protocol/codec.ts:1: imports shared/sim/index.ts (shared's parts depend one way: protocol <- sim <- replay)",
    ])
  })

  it('finds value cycles, through index files too, and ignores type-only ones', () => {
    const cycles = valueCycles(
      fixture({
        'a/x.ts': "import { y } from './y.ts'\n",
        'a/y.ts': "export { z } from './index.ts'\n",
        'a/index.ts': "export { x } from './x.ts'\n",
        'b/p.ts': "import type { Q } from './q.ts'\n",
        'b/q.ts': "import { p } from './p.ts'\n",
        'c/r.ts': "import { type S } from './s.ts'\n",
        'c/s.ts': "import { r } from './r.ts'\n",
      }),
    )
    expect(cycles).toEqual([
      ['a/index.ts', 'a/x.ts', 'a/y.ts'],
      ['c/r.ts', 'c/s.ts'],
    ])
  })
})

describe('the repository', () => {
  const files = repositoryFiles()

  it('has the layers to check', () => {
    for (const layer of ['engine', 'shared', 'server', 'client', 'bots', 'bench', 'sdk']) {
      expect(
        [...files.keys()].some((f) => f.startsWith(`${layer}/`)),
        layer,
      ).toBe(true)
    }
  })

  it('imports across layers and folders only as the layers allow', () => {
    expect(layerViolations(files)).toEqual([])
  })

  it('has no value import cycle', () => {
    expect(valueCycles(files).map((cycle) => cycle.join(' -> '))).toEqual([])
  })

  it('has an index.ts in every folder of a product layer', () => {
    const missing: string[] = []
    const folders = new Set<string>()
    for (const file of files.keys()) {
      if (!(PRODUCT as readonly string[]).includes(file.split('/')[0])) continue
      for (let dir = posix.dirname(file); dir !== '.'; dir = posix.dirname(dir)) folders.add(dir)
    }
    for (const dir of folders) {
      if (!existsSync(`${dir}/index.ts`) || !statSync(`${dir}/index.ts`).isFile()) missing.push(dir)
    }
    expect(missing.sort()).toEqual([])
  })
})
