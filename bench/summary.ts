/*
 * Order statistics of step times, with no Node imports so the benchmark page can use them too.
 * Median and p95 are robust to the odd garbage-collection pause; the mean is not, but it is what
 * a server pays over a minute of ticks, so both are reported.
 */

/** Order statistics of a list of step times (ms). */
export interface Summary {
  /** Number of samples. */
  n: number
  median: number
  p95: number
  mean: number
  min: number
  max: number
}

/** The value below which a fraction q (0..1) of the sorted samples lie, by linear interpolation. */
export function quantile(sorted: readonly number[], q: number): number {
  if (sorted.length === 0) return Number.NaN
  const position = (sorted.length - 1) * q
  const lo = Math.floor(position)
  const hi = Math.min(lo + 1, sorted.length - 1)
  return sorted[lo] + (sorted[hi] - sorted[lo]) * (position - lo)
}

/** Median of the samples (ms). */
export function median(samples: readonly number[]): number {
  return quantile(
    [...samples].sort((a, b) => a - b),
    0.5,
  )
}

/** 95th percentile of the samples (ms). */
export function p95(samples: readonly number[]): number {
  return quantile(
    [...samples].sort((a, b) => a - b),
    0.95,
  )
}

/** Median, p95, mean, min and max of the samples. */
export function summarize(samples: readonly number[]): Summary {
  const sorted = [...samples].sort((a, b) => a - b)
  let sum = 0
  for (const s of sorted) sum += s
  return {
    n: sorted.length,
    median: quantile(sorted, 0.5),
    p95: quantile(sorted, 0.95),
    mean: sorted.length > 0 ? sum / sorted.length : Number.NaN,
    min: sorted.length > 0 ? sorted[0] : Number.NaN,
    max: sorted.length > 0 ? sorted[sorted.length - 1] : Number.NaN,
  }
}

/**
 * The median over rounds of Concord's time over another engine's in the same round (`chunk` steps
 * each, taken back to back, so both meet the same machine load); null when no round can be read
 * (a round whose time reads 0). A busy machine slows a few rounds, not their median.
 */
export function medianRoundRatio(
  concord: readonly number[],
  other: readonly number[],
  chunk: number,
): number | null {
  const n = Math.min(concord.length, other.length)
  const ratios: number[] = []
  for (let from = 0; from + chunk <= n; from += chunk) {
    let c = 0
    let o = 0
    for (let i = from; i < from + chunk; i++) {
      c += concord[i]
      o += other[i]
    }
    if (c > 0 && o > 0) ratios.push(c / o)
  }
  if (ratios.length === 0) return null
  ratios.sort((a, b) => a - b)
  const mid = ratios.length >> 1
  return ratios.length % 2 === 1 ? ratios[mid] : (ratios[mid - 1] + ratios[mid]) / 2
}

/**
 * The spread of medianRoundRatio over a run: the run's rounds in four consecutive quarters, the
 * median round ratio of each, lowest and highest; null with fewer than four rounds or a quarter
 * with no readable round.
 */
export function quarterRatios(
  concord: readonly number[],
  other: readonly number[],
  chunk: number,
): { low: number; high: number } | null {
  const rounds = Math.floor(Math.min(concord.length, other.length) / chunk)
  if (rounds < 4) return null
  const medians: number[] = []
  for (let q = 0; q < 4; q++) {
    const from = Math.floor((q * rounds) / 4) * chunk
    const to = Math.floor(((q + 1) * rounds) / 4) * chunk
    const m = medianRoundRatio(concord.slice(from, to), other.slice(from, to), chunk)
    if (m === null) return null
    medians.push(m)
  }
  return { low: Math.min(...medians), high: Math.max(...medians) }
}
