/*
 * What a predicting client pays per rollback (PredictClient): copy the confirmed simulation
 * (cloneSimulation: world save + load) and re-simulate 4, 8 or 16 ticks, in a 20-row pyramid (210
 * boxes) and a 1,000-body pile, both awake. No Node imports: bench:lockstep runs it in Node and
 * bench:lockstep-browser bundles it into a Chromium page (rollback-cost-page.ts), so both
 * environments time identical code on identical worlds. Each figure is the median of `reps` runs
 * (ms) after two untimed rounds of the deepest rollback; a fresh copy per run, so no run
 * re-simulates an already stepped world.
 */

import { pileScene, pyramidScene, type SceneBlueprint } from '../engine/index.ts'
import { sandbox } from '../games/index.ts'
import { cloneSimulation, RoomSimulation, worldFromBlueprint } from '../shared/index.ts'
import { median } from './summary.ts'

/** One scene's rollback cost: medians in ms. */
export interface RollbackCost {
  bodies: number
  awake: number
  reps: number
  /** The copy alone (ms). */
  copyMs: number
  /** Copy + 4, 8, 16 re-simulated ticks (ms). */
  rollback4Ms: number
  rollback8Ms: number
  rollback16Ms: number
}

/** Time copy + re-simulation in `blueprint` after `warmTicks` ticks, median of `reps` runs each. */
export function measureRollbackCost(
  blueprint: SceneBlueprint,
  warmTicks: number,
  reps: number,
): RollbackCost {
  const sim = new RoomSimulation({
    game: sandbox,
    name: 'bench',
    scene: 'empty',
    maxBodies: 5000,
    controls: true,
  })
  const built = worldFromBlueprint(blueprint)
  sim.loadWorld(blueprint.name, built.world, built.joints)
  for (let i = 0; i < warmTicks; i++) sim.runTick()
  const options = { maxBodies: 5000, controls: true, name: '' }
  const time = (depth: number): number => {
    const samples: number[] = []
    for (let r = 0; r < reps; r++) {
      const t = performance.now()
      const copy = cloneSimulation(sim, options)
      for (let k = 0; k < depth; k++) copy.runTick()
      samples.push(performance.now() - t)
    }
    return median(samples)
  }
  // Warm the JIT on the deepest rollback first (a browser's first runs are several times slower).
  time(16)
  time(16)
  return {
    bodies: sim.world.bodyCount,
    awake: sim.world.awakeBodyCount(),
    reps,
    copyMs: time(0),
    rollback4Ms: time(4),
    rollback8Ms: time(8),
    rollback16Ms: time(16),
  }
}

/** Both scenes: the 210-box pyramid (10 warm ticks) and the 1,000-body pile (30 warm ticks). */
export function measureRollbackScenes(reps: number): { pyramid210: RollbackCost; pile1000: RollbackCost } {
  return {
    pyramid210: measureRollbackCost(pyramidScene(20), 10, reps),
    pile1000: measureRollbackCost(pileScene(1000), 30, reps),
  }
}

/** One printed line per scene. */
export function formatRollbackCost(where: string, name: string, r: RollbackCost): string {
  return (
    `rollback in ${where}, ${name} (${r.bodies} bodies, ${r.awake} awake), median of ${r.reps}: ` +
    `copy ${r.copyMs.toFixed(2)} ms; copy + 4 ticks ${r.rollback4Ms.toFixed(2)} ms, ` +
    `+ 8 ${r.rollback8Ms.toFixed(2)} ms, + 16 ${r.rollback16Ms.toFixed(2)} ms`
  )
}
