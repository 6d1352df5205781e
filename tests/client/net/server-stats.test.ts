/*
 * The HUD's server tick time from Prometheus text: the mean over an interval is the difference of
 * the histogram's _sum divided by the difference of its _count (hand-computed values below).
 */
import { describe, expect, it } from 'vitest'
import { meanTickMs } from '../../../client/net/server-stats.ts'

const text = (sum: number, count: number): string =>
  [
    '# HELP concord_room_tick_seconds Time to run one room tick: inputs, step, snapshots',
    '# TYPE concord_room_tick_seconds histogram',
    'concord_room_tick_seconds_bucket{le="0.0001"} 10',
    `concord_room_tick_seconds_bucket{le="+Inf"} ${count}`,
    `concord_room_tick_seconds_sum ${sum}`,
    `concord_room_tick_seconds_count ${count}`,
  ].join('\n')

describe('meanTickMs', () => {
  it('averages over the whole run on the first read', () => {
    expect(meanTickMs(text(0.6, 1200), null)?.meanMs).toBeCloseTo(0.5, 12)
  })

  it('averages over the interval between two reads', () => {
    const first = meanTickMs(text(0.6, 1200), null)!
    // 300 more ticks that took 0.15 s in all: 0.5 ms each.
    expect(meanTickMs(text(0.75, 1500), first)?.meanMs).toBeCloseTo(0.5, 12)
    // 300 ticks taking 0.6 s: 2 ms each.
    expect(meanTickMs(text(1.2, 1500), first)?.meanMs).toBeCloseTo(2, 12)
  })

  it('sums the series of every worker', () => {
    const workers = (sums: number[], counts: number[]): string =>
      sums
        .map((sum, i) =>
          [
            `concord_room_tick_seconds_sum{worker="${i + 1}"} ${sum}`,
            `concord_room_tick_seconds_count{worker="${i + 1}"} ${counts[i]}`,
          ].join('\n'),
        )
        .join('\n')
    const first = meanTickMs(workers([0.6, 0], [1200, 0]), null)!
    expect(first.meanMs).toBeCloseTo(0.5, 12)
    // Worker 1: 100 ticks in 0.1 s; worker 2: 300 ticks in 0.9 s; 400 ticks in 1 s: 2.5 ms each.
    expect(meanTickMs(workers([0.7, 0.9], [1300, 300]), first)?.meanMs).toBeCloseTo(2.5, 12)
  })

  it('reports nothing when no tick ran, and null when the histogram is missing', () => {
    const first = meanTickMs(text(0.6, 1200), null)!
    expect(meanTickMs(text(0.6, 1200), first)?.meanMs).toBeNull()
    expect(meanTickMs('process_cpu_seconds_total 1', null)).toBeNull()
  })
})
