/*
 * The page side of the browser determinism test (engine-determinism.test.ts): bundled with esbuild
 * for the browser and injected into a blank page in headless Chromium. The Node side imports the
 * same functions, so both environments run identical code on identical inputs.
 */
import { atan2, cos, createWorld, sin } from '../../engine/index.ts'
import {
  atan2Results,
  buildMachines,
  buildMixedScene,
  digest,
  driveMachines,
  GOLDEN_STEPS,
  runMixedScene,
  runVocabulary,
  trigInputs,
  trigResults,
} from '../engine/determinism-fixtures.ts'

/** The mixed scene's hash every 100 steps up to GOLDEN_STEPS (the last one is the golden hash). */
export function runGolden(): number[] {
  const world = createWorld()
  const handles = buildMixedScene(world)
  const hashes: number[] = []
  for (let tick = 100; tick <= GOLDEN_STEPS; tick += 100) {
    runMixedScene(world, handles, tick)
    hashes.push(world.hash())
  }
  return hashes
}

/** The machines scene's hash (every joint kind, springs, motors, a break) every 100 steps up to 600. */
export function runMachines(): number[] {
  const world = createWorld()
  buildMachines(world)
  const hashes: number[] = []
  for (let i = 1; i <= 600; i++) {
    driveMachines(world)
    world.step()
    if (i % 100 === 0) hashes.push(world.hash())
  }
  return hashes
}

/** Digests of the engine's trig over the shared inputs, and the host's Math results for comparison. */
export function trigReport() {
  const inputs = trigInputs()
  return {
    inputs: digest(inputs),
    sin: digest(trigResults(inputs, sin)),
    cos: digest(trigResults(inputs, cos)),
    atan2: digest(atan2Results(inputs, atan2)),
    mathSin: Array.from(trigResults(inputs, Math.sin)),
    mathCos: Array.from(trigResults(inputs, Math.cos)),
    mathAtan2: Array.from(atan2Results(inputs, Math.atan2)),
  }
}

/**
 * The vocabulary scene (compound, capsule, segment, rounded and decompose()d shapes, filters,
 * sensors, rolling resistance, conveyors, events and queries): the world's hash and the hash of the
 * events and query results of every step, every 500 steps (determinism-fixtures.ts runVocabulary).
 */
export function runVocabularyScene(): number[] {
  return runVocabulary()
}

/** The handle the test calls through page.evaluate. */
export interface EngineCheck {
  runGolden: typeof runGolden
  runMachines: typeof runMachines
  runVocabularyScene: typeof runVocabularyScene
  trigReport: typeof trigReport
}

;(globalThis as unknown as { concordEngineCheck: EngineCheck }).concordEngineCheck = {
  runGolden,
  runMachines,
  runVocabularyScene,
  trigReport,
}
