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
 * Concord's mean step time over another engine's in each quarter of the timed steps (both lists
 * hold the same steps in the same rounds), lowest and highest; null when a quarter's mean reads 0.
 */
export function quarterRatios(
  concord: readonly number[],
  other: readonly number[],
): { low: number; high: number } | null {
  const n = Math.min(concord.length, other.length)
  if (n < 4) return null
  const ratios: number[] = []
  for (let q = 0; q < 4; q++) {
    const from = Math.floor((q * n) / 4)
    const to = Math.floor(((q + 1) * n) / 4)
    let c = 0
    let o = 0
    for (let i = from; i < to; i++) {
      c += concord[i]
      o += other[i]
    }
    if (c === 0 || o === 0) return null
    ratios.push(c / o)
  }
  return { low: Math.min(...ratios), high: Math.max(...ratios) }
}
