/*
 * Every engine of the comparison behind one interface: createPeer(engine, blueprint, sleep) loads
 * the engine's module on first use (so a child process running one engine loads only that one)
 * and builds the blueprint in a new world. The terminal benchmark and the benchmark page both go
 * through here.
 */
import type { SceneBlueprint } from '../../engine/index.ts'
import type { PeerWorld } from '../stats.ts'

/** The engines compared, Concord first. */
export const PEER_ENGINES = [
  'concord',
  'box2d3-wasm',
  'box2d3-wasm-compat',
  'rapier',
  'box2d-wasm',
  'phaser-box2d',
  'matter-js',
  '@box2d/core',
  'planck',
] as const

/** One of the compared engines. */
export type PeerEngine = (typeof PEER_ENGINES)[number]

/** What each engine is, for tables and the page. */
export const PEER_DESCRIPTIONS: Readonly<Record<PeerEngine, string>> = {
  concord: 'Concord (TypeScript, deterministic)',
  'box2d3-wasm': "Box2D v3 in WebAssembly (the package entry's build: deluxe, with SIMD, in Node)",
  'box2d3-wasm-compat': 'Box2D v3 in WebAssembly, compat build (no SIMD, no threads)',
  rapier: 'Rapier in WebAssembly (rapier2d-compat)',
  'box2d-wasm': 'Box2D 2.4 in WebAssembly',
  'phaser-box2d': 'Box2D v3.0 ported to JavaScript',
  'matter-js': 'matter-js (JavaScript)',
  '@box2d/core': 'Box2D 2.4 ported to TypeScript',
  planck: 'planck.js (Box2D 2.x in JavaScript)',
}

/** Whether a name is one of the compared engines. */
export function isPeerEngine(name: string): name is PeerEngine {
  return (PEER_ENGINES as readonly string[]).includes(name)
}

/** Loads `engine` if needed and builds the blueprint in a new world, sleeping on or off. */
export async function createPeer(
  engine: PeerEngine,
  blueprint: SceneBlueprint,
  sleep: boolean,
): Promise<PeerWorld> {
  switch (engine) {
    case 'concord': {
      const { ConcordPeer } = await import('./concord-peer.ts')
      return new ConcordPeer(blueprint, sleep)
    }
    case 'box2d3-wasm':
      return (await import('./box2d3-wasm-peer.ts')).Box2D3WasmPeer.create(blueprint, sleep)
    case 'box2d3-wasm-compat':
      return (await import('./box2d3-wasm-peer.ts')).Box2D3WasmPeer.create(blueprint, sleep, 'compat')
    case 'rapier':
      return (await import('./rapier-peer.ts')).RapierPeer.create(blueprint, sleep)
    case 'box2d-wasm':
      return (await import('./box2d-wasm-peer.ts')).Box2DWasmPeer.create(blueprint, sleep)
    case 'phaser-box2d':
      return (await import('./phaser-box2d-peer.ts')).PhaserBox2DPeer.create(blueprint, sleep)
    case 'matter-js':
      return (await import('./matter-peer.ts')).MatterPeer.create(blueprint, sleep)
    case '@box2d/core':
      return (await import('./box2d-core-peer.ts')).Box2DCorePeer.create(blueprint, sleep)
    case 'planck':
      return (await import('./planck-peer.ts')).PlanckPeer.create(blueprint, sleep)
  }
}
