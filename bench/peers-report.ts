/*
 * The terminal tables of `npm run bench:peers`: per case every engine's step times, CPU, memory
 * and end state; then Concord's ratio to each peer; then the scaling run as cost per body.
 */
import type { CaseResult } from './peers-bench.ts'
import { formatTable } from './stats.ts'

const fmt = (x: number | null | undefined, digits = 2): string =>
  x === null || x === undefined || !Number.isFinite(x) ? '-' : x.toFixed(digits)

/** One line per engine and case, then the ratio table. */
export function printCases(cases: readonly CaseResult[]): void {
  const rows: string[][] = []
  for (const c of cases) {
    for (const r of c.rows) {
      const q = r.quality
      rows.push([
        `${c.scene} sleep ${c.sleep ? 'on' : 'off'}`,
        r.engine,
        String(r.bodies),
        fmt(r.steps.mean, 3),
        fmt(r.steps.median, 3),
        fmt(r.steps.p95, 3),
        fmt(r.cpuMsPerStep, 3),
        fmt(r.peakRssMB, 0),
        fmt(r.sceneRssMB, 0),
        q.verdict,
        fmt(q.maxDrift, 2),
        fmt(q.topDx, 3),
        fmt(q.maxStretch, 3),
        q.sleptAfter === null ? (c.sleep ? 'never' : '-') : `${q.sleptAfter.toFixed(1)} s`,
        String(q.awake),
        c.concordOverMean[r.engine] === undefined ? '' : fmt(c.concordOverMean[r.engine]),
      ])
    }
  }
  const header = ['case', 'engine', 'bodies', 'mean ms', 'median', 'p95', 'cpu ms', 'peak MB', '+MB']
  const quality = ['end state', 'drift m', 'top dx', 'stretch', 'asleep', 'awake', 'concord/this']
  console.log(`\n${formatTable([...header, ...quality], rows)}\n`)
  const peers = [...new Set(cases.flatMap((c) => c.rows.map((r) => r.engine)))].filter((e) => e !== 'concord')
  const ratioRows = cases.map((c) => [
    `${c.scene} sleep ${c.sleep ? 'on' : 'off'}`,
    ...peers.map((p) => fmt(c.concordOverMean[p])),
  ])
  console.log(formatTable(['concord / peer (mean)', ...peers], ratioRows))
  console.log('Concord time over the peer time in the same interleaved run: below 1, Concord is faster.\n')
}

/** Cost per body in the scaling run. */
export function printScaling(cases: readonly CaseResult[]): void {
  const engines = [...new Set(cases.flatMap((c) => c.rows.map((r) => r.engine)))]
  const rows = cases.map((c) => [
    String(c.count),
    String(c.timedSteps),
    ...engines.flatMap((engine) => {
      const row = c.rows.find((r) => r.engine === engine)
      return row ? [fmt(row.steps.mean, 2), fmt((row.steps.mean * 1000) / c.count, 2)] : ['-', '-']
    }),
    ...engines.filter((e) => e !== 'concord').map((e) => fmt(c.concordOverMean[e])),
  ])
  const header = [
    'pile bodies',
    'steps',
    ...engines.flatMap((e) => [`${e} ms`, 'us/body']),
    ...engines.filter((e) => e !== 'concord').map((e) => `concord/${e}`),
  ]
  console.log(`${formatTable(header, rows)}\nsleep off; means per step; warm-up excluded\n`)
}
