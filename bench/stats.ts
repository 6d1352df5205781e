/*
 * What the engine benchmark measures and how it records it.
 *
 * Every engine under test (Concord and its peers) is wrapped in a PeerWorld: a world built from a
 * scene blueprint that can step 1/60 s and report its bodies' state in blueprint order. The harness
 * times each step with performance.now(), summarizes the samples with the order statistics below
 * (median and p95 are robust to the odd garbage-collection pause; the mean is not), and saves the
 * numbers with the machine they were measured on, so results from different runs and machines can
 * be told apart. It also says how each scene ended (checkScene): a fast engine whose pyramid falls
 * is not a fast engine.
 */
import { execFileSync } from 'node:child_process'
import { mkdirSync, writeFileSync } from 'node:fs'
import os from 'node:os'
import { dirname } from 'node:path'
import { PerformanceObserver } from 'node:perf_hooks'
import type { BodyDef, SceneBlueprint } from '../engine/index.ts'
import { median } from './summary.ts'

/** One engine's world, built from a scene blueprint, as the benchmark drives it. */
export interface PeerWorld {
  /** Engine name as printed: 'concord', 'planck', 'box2d-wasm', ... */
  readonly engine: string
  /** Advances exactly 1/60 s. */
  step(): void
  /** Adds one body after the build (scenes whose bodies arrive over time); it reads back after the rest. */
  addBody(def: BodyDef): void
  /** Per blueprint body, in blueprint order: x, y (body origin, m), vx, vy (m/s); 4 numbers each. */
  readBodies(): Float64Array
  /** Bodies currently awake (dynamic and kinematic). */
  awakeCount(): number
  /** Frees whatever the engine holds outside the JavaScript heap. */
  dispose(): void
}

export { median, p95, quantile, type Summary, summarize } from './summary.ts'

/** The machine and software a result was measured on. */
export interface MachineInfo {
  cpu: string
  cores: number
  totalMemoryGiB: number
  platform: string
  release: string
  node: string
  v8: string
  /** 1-minute load average when the run started (the machine is shared). */
  loadAverage: number
  date: string
  /** Repository commit the run measured, or 'unknown'. */
  commit: string
}

function gitCommit(): string {
  try {
    const head = execFileSync('git', ['rev-parse', '--short', 'HEAD'], { encoding: 'utf8' }).trim()
    const dirty = execFileSync('git', ['status', '--porcelain', '--', 'engine'], { encoding: 'utf8' }).trim()
    return dirty === '' ? head : `${head}+engine-changes`
  } catch {
    return 'unknown'
  }
}

/** Describes this machine, Node and the repository commit. */
export function machineInfo(): MachineInfo {
  const cpus = os.cpus()
  return {
    cpu: cpus[0]?.model ?? 'unknown',
    cores: cpus.length,
    totalMemoryGiB: Math.round((os.totalmem() / 2 ** 30) * 10) / 10,
    platform: os.platform(),
    release: os.release(),
    node: process.version,
    v8: process.versions.v8,
    loadAverage: os.loadavg()[0],
    date: new Date().toISOString(),
    commit: gitCommit(),
  }
}

/** Writes a result as indented JSON, creating the folder if needed. */
export function saveResults(path: string, result: unknown): void {
  mkdirSync(dirname(path), { recursive: true })
  writeFileSync(path, `${JSON.stringify(result, null, 2)}\n`)
}

/** Renders rows of cells as a plain-text table with right-aligned columns after the first. */
export function formatTable(header: readonly string[], rows: readonly (readonly string[])[]): string {
  const widths = header.map((h, c) => Math.max(h.length, ...rows.map((r) => (r[c] ?? '').length)))
  const line = (cells: readonly string[]): string =>
    cells.map((cell, c) => (c === 0 ? cell.padEnd(widths[c]) : cell.padStart(widths[c]))).join('  ')
  return [line(header), widths.map((w) => '-'.repeat(w)).join('  '), ...rows.map(line)].join('\n')
}

/** A garbage-collection pause: start on the performance.now() clock and duration (ms). */
export interface GcPause {
  start: number
  duration: number
}

/**
 * Starts recording garbage-collection pauses; `stop()` resolves with every pause since. Node
 * delivers the entries late (measured: a case's pauses arrive during the next case), so record
 * over the whole run and let stop() wait a few timer turns for the stragglers.
 */
export function recordGcPauses(): { stop(): Promise<GcPause[]> } {
  const pauses: GcPause[] = []
  const observer = new PerformanceObserver((list) => {
    for (const entry of list.getEntries()) pauses.push({ start: entry.startTime, duration: entry.duration })
  })
  observer.observe({ entryTypes: ['gc'] })
  return {
    async stop() {
      for (let turn = 0; turn < 5; turn++) await new Promise((resolve) => setTimeout(resolve, 10))
      observer.disconnect()
      return pauses
    },
  }
}

/**
 * The ratio a/b paired in time: the step samples of both engines, in order, fall into rounds of
 * `chunk` steps taken back to back; the result is the median over rounds of the ratio of the two
 * round medians. Slow drifts in machine load and in the scene's cost cancel within a round.
 */
export function pairedRatio(a: readonly number[], b: readonly number[], chunk: number): number {
  const ratios: number[] = []
  for (let i = 0; i < Math.min(a.length, b.length); i += chunk) {
    ratios.push(median(a.slice(i, i + chunk)) / median(b.slice(i, i + chunk)))
  }
  return median(ratios)
}

/** Which end-state test a scene gets. */
export type SceneKind = 'pyramid' | 'pile'

/**
 * A pyramid stands while no box has moved this far from its start (m). Box2D 2.x keeps a 0.01 m
 * skin on polygons, so its pyramids rise about 0.015 m per row while settling; a collapse moves
 * boxes metres.
 */
const STANDING_DRIFT = 1

/** How a scene looks after the run, for one engine. */
export interface SceneCheck {
  /** Final minus initial position of the last blueprint body: the pyramid's top box (m). */
  topDx: number
  topDy: number
  /** Largest distance any dynamic body moved from its start (m). */
  maxDrift: number
  /** Fastest dynamic body (m/s). */
  maxSpeed: number
  /** Highest dynamic body origin (m). */
  maxY: number
  /** Dynamic bodies below the ground or outside the container's walls. */
  escaped: number
  awake: number
  /** Pyramids: 'standing' when no box moved 1 m or more, else 'FELL'; pile: 'contained' or 'N ESCAPED'. */
  verdict: string
}

/** Measures how a scene ended in one engine from its bodies at the start and end (readBodies). */
export function checkScene(
  kind: SceneKind,
  blueprint: SceneBlueprint,
  start: Float64Array,
  end: Float64Array,
  awake: number,
): SceneCheck {
  let maxDrift = 0
  let maxSpeed = 0
  let maxY = Number.NEGATIVE_INFINITY
  let escaped = 0
  let wallX = Number.POSITIVE_INFINITY
  if (kind === 'pile') {
    wallX = 0
    for (const def of blueprint.bodies)
      if (def.type === 'static') wallX = Math.max(wallX, Math.abs(def.position?.x ?? 0))
  }
  blueprint.bodies.forEach((def, i) => {
    if (def.type === 'static') return
    const [x0, y0] = [start[i * 4], start[i * 4 + 1]]
    const [x, y, vx, vy] = end.subarray(i * 4, i * 4 + 4)
    maxDrift = Math.max(maxDrift, Math.sqrt((x - x0) ** 2 + (y - y0) ** 2))
    maxSpeed = Math.max(maxSpeed, Math.sqrt(vx * vx + vy * vy))
    maxY = Math.max(maxY, y)
    if (!(y > -0.25 && Math.abs(x) < wallX)) escaped++
  })
  const last = blueprint.bodies.length - 1
  const topDx = end[last * 4] - start[last * 4]
  const topDy = end[last * 4 + 1] - start[last * 4 + 1]
  const verdict =
    kind === 'pyramid'
      ? maxDrift < STANDING_DRIFT && escaped === 0
        ? 'standing'
        : 'FELL'
      : escaped === 0
        ? 'contained'
        : `${escaped} ESCAPED`
  return { topDx, topDy, maxDrift, maxSpeed, maxY, escaped, awake, verdict }
}
