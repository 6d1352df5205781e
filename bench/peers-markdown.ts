/*
 * Markdown tables of a saved `npm run bench:peers` result, for bench/README.md. `npm run
 * bench:peers` writes them next to its JSON (peers.md); to regenerate from a saved file run
 * `npx tsx bench/peers-markdown.ts bench/results/peers.json`.
 */
import { readFileSync, writeFileSync } from 'node:fs'
import { fileURLToPath } from 'node:url'
import type { CaseResult } from './peers-bench.ts'

const fmt = (x: number | null | undefined, digits = 2): string =>
  x === null || x === undefined || !Number.isFinite(x) ? '-' : x.toFixed(digits)

function table(header: readonly string[], rows: readonly (readonly string[])[]): string {
  const line = (cells: readonly string[]): string => `| ${cells.join(' | ')} |`
  return [line(header), line(header.map((_, i) => (i === 0 ? '---' : '---:'))), ...rows.map(line)].join('\n')
}

/** The ratio table, one table per case, and the scaling table. */
export function peersMarkdown(cases: readonly CaseResult[], scaling: readonly CaseResult[]): string {
  const parts: string[] = []
  const peers = [...new Set(cases.flatMap((c) => c.rows.map((r) => r.engine)))].filter((e) => e !== 'concord')
  if (cases.length > 0) {
    const ratio = (c: CaseResult, peer: string, of: (r: CaseResult['rows'][number]) => number): string => {
      const concord = c.rows.find((r) => r.engine === 'concord')
      const other = c.rows.find((r) => r.engine === peer)
      return concord && other ? fmt(of(concord) / of(other)) : '-'
    }
    const ratioTable = (title: string, of: (r: CaseResult['rows'][number]) => number): void => {
      parts.push(
        `### Concord over each peer: ${title} (same interleaved run; below 1: Concord is faster)\n`,
        table(
          ['case', ...peers],
          cases.map((c) => [
            `${c.scene} sleep ${c.sleep ? 'on' : 'off'}`,
            ...peers.map((p) => ratio(c, p, of)),
          ]),
        ),
        '',
      )
    }
    ratioTable('CPU time per step', (r) => r.cpuMsPerStep)
    ratioTable('median wall time per step', (r) => r.steps.median)
    ratioTable('mean wall time per step', (r) => r.steps.mean)
  }
  for (const c of cases) {
    parts.push(
      `\n### ${c.scene}, sleep ${c.sleep ? 'on' : 'off'} (${c.timedSteps} timed steps after ${c.warmupSteps} warm-up)\n`,
      table(
        [
          'engine',
          'bodies',
          'mean ms',
          'median',
          'p95',
          'CPU ms',
          'peak MB',
          'end state',
          'drift m',
          'top dx m',
          'joint stretch m',
          'asleep after',
        ],
        c.rows.map((r) => {
          const q = r.quality
          return [
            r.engine,
            String(r.bodies),
            fmt(r.steps.mean, 3),
            fmt(r.steps.median, 3),
            fmt(r.steps.p95, 3),
            fmt(r.cpuMsPerStep, 3),
            fmt(r.peakRssMB, 0),
            q.verdict,
            fmt(q.maxDrift, 2),
            fmt(q.topDx, 3),
            fmt(q.maxStretch, 3),
            q.sleptAfter === null ? (c.sleep ? 'not in the run' : '-') : `${q.sleptAfter.toFixed(1)} s`,
          ]
        }),
      ),
    )
  }
  if (scaling.length > 0) {
    const engines = [...new Set(scaling.flatMap((c) => c.rows.map((r) => r.engine)))]
    parts.push(
      '\n### Scaling: the pile, sleep off (mean wall ms per step; wall and CPU microseconds per body per step)\n',
      table(
        [
          'bodies',
          'timed steps',
          ...engines.flatMap((e) => [`${e} ms`, 'us/body', 'CPU us/body']),
          ...engines.slice(1).map((e) => `concord/${e} (CPU)`),
        ],
        scaling.map((c) => [
          String(c.count),
          String(c.timedSteps),
          ...engines.flatMap((e) => {
            const row = c.rows.find((r) => r.engine === e)
            if (!row) return ['-', '-', '-']
            return [
              fmt(row.steps.mean, 2),
              fmt((row.steps.mean * 1000) / c.count, 2),
              fmt((row.cpuMsPerStep * 1000) / c.count, 2),
            ]
          }),
          ...engines.slice(1).map((e) => {
            const concord = c.rows.find((r) => r.engine === 'concord')
            const other = c.rows.find((r) => r.engine === e)
            return concord && other ? fmt(concord.cpuMsPerStep / other.cpuMsPerStep) : '-'
          }),
        ]),
      ),
    )
  }
  return `${parts.join('\n')}\n`
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const file = process.argv[2] ?? 'bench/results/peers.json'
  const saved = JSON.parse(readFileSync(file, 'utf8')) as { cases?: CaseResult[]; scaling?: CaseResult[] }
  const markdown = peersMarkdown(saved.cases ?? [], saved.scaling ?? [])
  const out = file.replace(/\.json$/, '.md')
  writeFileSync(out, markdown)
  console.log(`wrote ${out}`)
}
