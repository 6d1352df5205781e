/*
 * The engine's internals that the benchmarks measure directly, and nothing else: the broadphase
 * and its pair buffer (bench/broad-phase-bench.ts times them against brute force). Only bench/ may
 * import this file (tests/architecture/layers.test.ts enforces it); everything else uses index.ts.
 */
export { BroadPhase, PairBuffer } from './collision/index.ts'
