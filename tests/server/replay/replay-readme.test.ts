/*
 * The README's "Recording and replays" promises that are not behaviour tested elsewhere: the log
 * size table is bench/results/replay.json as saved by `npm run bench:replay` (rounded as printed),
 * and the defaults it names are the server's.
 */
import { readFileSync } from 'node:fs'
import { describe, expect, it } from 'vitest'
import { SETTINGS } from '../../../server/config/config.ts'

const readme = readFileSync('README.md', 'utf8')
const results = JSON.parse(readFileSync('bench/results/replay.json', 'utf8')) as {
  perHour: Array<{
    room: string
    variant: string
    recordsMbPerHour: number
    keyframesMbPerHour: number
    mbPerHour: number
  }>
}
const fallback = (key: string): unknown => SETTINGS.find((s) => s.key === key)?.fallback

/** As the README prints a figure: whole MB from 10 up, one decimal below. */
const printed = (mb: number): string => (mb >= 10 ? `${Math.round(mb)} MB` : `${mb.toFixed(1)} MB`)

describe('README, Recording and replays', () => {
  it('gives the log sizes the bench saved', () => {
    expect(readme).toMatch(/^\| log bytes per room hour \| records \| keyframes \| total \|$/m)
    const rows = [
      ['busy: 1,000-body pile, 5 players dragging at 20 Hz, defaults', 'busy', 'default'],
      ['busy, no keyframe budget', 'busy', 'no budget'],
      ['busy, no keyframe budget, keyframes raw', 'busy', 'no budget, raw'],
      ['quiet: 210-box pyramid, one idle player, defaults', 'quiet', 'default'],
      ['quiet, no keyframe budget', 'quiet', 'no budget'],
      ['quiet, no keyframe budget, keyframes raw', 'quiet', 'no budget, raw'],
    ] as const
    for (const [label, room, variant] of rows) {
      const line = readme.split('\n').find((l) => l.startsWith(`| ${label} |`))
      expect(line, label).toBeDefined()
      const cells = line!
        .split('|')
        .slice(2, -1)
        .map((c) => c.trim())
      const r = results.perHour.find((p) => p.room === room && p.variant === variant)!
      expect(cells, label).toEqual([
        printed(r.recordsMbPerHour),
        printed(r.keyframesMbPerHour),
        printed(r.mbPerHour),
      ])
    }
  })

  it('names the server defaults', () => {
    expect(readme).toContain(`\`--keyframe-budget\` (default ${fallback('keyframeBudget')} MB)`)
    expect(readme).toContain(`\`--keyframe-ticks\` (default ${fallback('keyframeTicks')} = 10 s)`)
    expect(readme).toContain(`\`--replay-keep\` (default ${fallback('replayKeep')})`)
    expect(fallback('replayMaxBytes')).toBe(256 * 1024 * 1024)
    expect(readme).toContain('`--replay-max-bytes` (default 256 MiB)')
    expect(fallback('replayFsync')).toBe('interval')
    expect(readme).toContain('`interval` (default)')
    expect(fallback('recover')).toBe(true)
    expect(readme).toContain('With `--recover` (default true while recording)')
  })
})
