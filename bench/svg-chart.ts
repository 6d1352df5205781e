/*
 * Two small hand-written SVG charts for the benchmark results (no plotting dependency): grouped
 * horizontal bars on a log axis (step time per engine, per scene) and lines over a log x axis
 * (cost per body against body count). Text is escaped; every number is checked finite before it
 * becomes a coordinate, so a missing engine leaves a gap rather than a broken file.
 */

/** One named series of values, one per group (null: no value). */
export interface BarSeries {
  name: string
  values: readonly (number | null)[]
}

/** One named line through (x, y) points. */
export interface LineSeries {
  name: string
  points: readonly (readonly [number, number])[]
}

const PALETTE = ['#d62728', '#1f77b4', '#2ca02c', '#ff7f0e', '#9467bd', '#8c564b', '#e377c2', '#7f7f7f']
const FONT = 'font-family="sans-serif" font-size="12"'

function escapeXml(text: string): string {
  return text.replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;').replace(/"/g, '&quot;')
}

function logTicks(min: number, max: number): number[] {
  const ticks: number[] = []
  for (let e = Math.floor(Math.log10(min)); e <= Math.ceil(Math.log10(max)); e++) {
    for (const m of [1, 2, 5]) {
      const t = m * 10 ** e
      if (t >= min * 0.999 && t <= max * 1.001) ticks.push(t)
    }
  }
  return ticks
}

function label(value: number): string {
  return value >= 100
    ? value.toFixed(0)
    : value >= 1
      ? String(Number(value.toPrecision(2)))
      : String(Number(value.toPrecision(1)))
}

function legend(names: readonly string[], x: number, y: number): string {
  return names
    .map(
      (name, i) =>
        `<rect x="${x}" y="${y + i * 16}" width="10" height="10" fill="${PALETTE[i % PALETTE.length]}"/>` +
        `<text x="${x + 14}" y="${y + i * 16 + 9}" ${FONT}>${escapeXml(name)}</text>`,
    )
    .join('')
}

/** Grouped horizontal bars on a log axis: one group per label, one bar per series. */
export function barChart(
  title: string,
  unit: string,
  groups: readonly string[],
  series: readonly BarSeries[],
): string {
  const values = series
    .flatMap((s) => s.values)
    .filter((v): v is number => v !== null && Number.isFinite(v) && v > 0)
  const min = 10 ** Math.floor(Math.log10(Math.min(...values)))
  const max = 10 ** Math.ceil(Math.log10(Math.max(...values)))
  const left = 110
  const plotWidth = 520
  const bar = 9
  const groupHeight = series.length * bar + 12
  const top = 40
  const height = top + groups.length * groupHeight + 40
  const width = left + plotWidth + 150
  const x = (v: number): number => left + (plotWidth * Math.log10(v / min)) / Math.log10(max / min)
  const parts = [
    `<svg xmlns="http://www.w3.org/2000/svg" width="${width}" height="${height}" viewBox="0 0 ${width} ${height}">`,
    `<rect width="100%" height="100%" fill="white"/>`,
    `<text x="${left}" y="20" ${FONT} font-weight="bold">${escapeXml(title)}</text>`,
  ]
  for (const t of logTicks(min, max)) {
    parts.push(`<line x1="${x(t)}" y1="${top - 4}" x2="${x(t)}" y2="${height - 34}" stroke="#ddd"/>`)
    parts.push(`<text x="${x(t)}" y="${height - 20}" ${FONT} text-anchor="middle">${label(t)}</text>`)
  }
  parts.push(
    `<text x="${left + plotWidth / 2}" y="${height - 4}" ${FONT} text-anchor="middle">${escapeXml(unit)} (log scale)</text>`,
  )
  groups.forEach((group, g) => {
    const y0 = top + g * groupHeight
    parts.push(
      `<text x="${left - 6}" y="${y0 + (series.length * bar) / 2 + 4}" ${FONT} text-anchor="end">${escapeXml(group)}</text>`,
    )
    series.forEach((s, i) => {
      const v = s.values[g]
      if (v === null || v === undefined || !Number.isFinite(v) || v <= 0) return
      parts.push(
        `<rect x="${left}" y="${y0 + i * bar}" width="${Math.max(1, x(v) - left).toFixed(1)}" height="${bar - 1}" fill="${PALETTE[i % PALETTE.length]}"><title>${escapeXml(`${s.name}: ${v.toPrecision(3)} ${unit}`)}</title></rect>`,
      )
    })
  })
  parts.push(
    legend(
      series.map((s) => s.name),
      left + plotWidth + 16,
      top,
    ),
    '</svg>',
  )
  return `${parts.join('\n')}\n`
}

/** Lines over a log x axis and a linear y axis from 0. */
export function lineChart(
  title: string,
  xUnit: string,
  yUnit: string,
  series: readonly LineSeries[],
): string {
  const points = series
    .flatMap((s) => s.points)
    .filter(([px, py]) => Number.isFinite(px) && Number.isFinite(py) && px > 0)
  const xMin = Math.min(...points.map((p) => p[0]))
  const xMax = Math.max(...points.map((p) => p[0]))
  const yMax = Math.max(...points.map((p) => p[1])) * 1.1
  const left = 60
  const top = 40
  const plotWidth = 520
  const plotHeight = 300
  const width = left + plotWidth + 160
  const height = top + plotHeight + 50
  const x = (v: number): number => left + (plotWidth * Math.log(v / xMin)) / Math.log(xMax / xMin)
  const y = (v: number): number => top + plotHeight - (plotHeight * v) / yMax
  const parts = [
    `<svg xmlns="http://www.w3.org/2000/svg" width="${width}" height="${height}" viewBox="0 0 ${width} ${height}">`,
    `<rect width="100%" height="100%" fill="white"/>`,
    `<text x="${left}" y="20" ${FONT} font-weight="bold">${escapeXml(title)}</text>`,
    `<line x1="${left}" y1="${top + plotHeight}" x2="${left + plotWidth}" y2="${top + plotHeight}" stroke="#888"/>`,
    `<line x1="${left}" y1="${top}" x2="${left}" y2="${top + plotHeight}" stroke="#888"/>`,
  ]
  const xs = [...new Set(points.map((p) => p[0]))].sort((a, b) => a - b)
  for (const t of xs)
    parts.push(`<text x="${x(t)}" y="${top + plotHeight + 16}" ${FONT} text-anchor="middle">${t}</text>`)
  for (let i = 0; i <= 5; i++) {
    const v = (yMax * i) / 5
    parts.push(`<line x1="${left}" y1="${y(v)}" x2="${left + plotWidth}" y2="${y(v)}" stroke="#eee"/>`)
    parts.push(`<text x="${left - 6}" y="${y(v) + 4}" ${FONT} text-anchor="end">${label(v)}</text>`)
  }
  parts.push(
    `<text x="${left + plotWidth / 2}" y="${height - 8}" ${FONT} text-anchor="middle">${escapeXml(xUnit)} (log scale)</text>`,
  )
  parts.push(
    `<text x="14" y="${top + plotHeight / 2}" ${FONT} text-anchor="middle" transform="rotate(-90 14 ${top + plotHeight / 2})">${escapeXml(yUnit)}</text>`,
  )
  series.forEach((s, i) => {
    const valid = s.points.filter(([px, py]) => Number.isFinite(px) && Number.isFinite(py) && px > 0)
    const color = PALETTE[i % PALETTE.length]
    const path = valid
      .map(([px, py], k) => `${k === 0 ? 'M' : 'L'}${x(px).toFixed(1)},${y(py).toFixed(1)}`)
      .join(' ')
    parts.push(`<path d="${path}" fill="none" stroke="${color}" stroke-width="2"/>`)
    for (const [px, py] of valid) {
      parts.push(
        `<circle cx="${x(px).toFixed(1)}" cy="${y(py).toFixed(1)}" r="3" fill="${color}"><title>${escapeXml(`${s.name}: ${px} bodies, ${py.toPrecision(3)} ${yUnit}`)}</title></circle>`,
      )
    }
  })
  parts.push(
    legend(
      series.map((s) => s.name),
      left + plotWidth + 16,
      top,
    ),
    '</svg>',
  )
  return `${parts.join('\n')}\n`
}
