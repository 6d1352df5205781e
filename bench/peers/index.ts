/*
 * The other engines that `npm run bench:peers` and the benchmark page run Concord's scenes in
 * (box2d3-wasm, box2d-wasm, @box2d/core, Rapier, matter-js, phaser-box2d, planck): one adapter per
 * engine behind one Peer interface, and the registry that lists them.
 */
export {
  BOX2D_POSITION_ITERATIONS,
  BOX2D_VELOCITY_ITERATIONS,
  BOX2D_WASM_BUILD,
  Box2DWasmPeer,
} from './box2d-wasm-peer.ts'
export { BOX2D3_SUB_STEPS, Box2D3WasmPeer } from './box2d3-wasm-peer.ts'
export { ConcordPeer } from './concord-peer.ts'
export {
  createPeer,
  isPeerEngine,
  PEER_DESCRIPTIONS,
  PEER_ENGINES,
  type PeerEngine,
} from './peer-registry.ts'
export { PLANCK_POSITION_ITERATIONS, PLANCK_VELOCITY_ITERATIONS, PlanckPeer } from './planck-peer.ts'
export { RapierPeer, rapierVersion } from './rapier-peer.ts'
export { setWasmLocator } from './wasm-location.ts'
