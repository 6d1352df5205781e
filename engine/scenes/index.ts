/*
 * The scenes, built in one place and reused by tests, benchmarks, the server and the client:
 * blueprints (bodies and joints as plain definitions) and the joint stress scenes.
 */
export { CHAIN_LINK_LENGTH, CHAIN_TOP, hangingChainScene, ragdollScene } from './joint-stress-scenes.ts'
export { MACHINES_LAYOUT, machinesScene } from './machine-scenes.ts'
export { PLAYGROUND_LAYOUT, playgroundScene } from './playground-scene.ts'
export { DEFAULT_SCENE, SCENES } from './scene-list.ts'
export {
  buildScene,
  cardHouseScene,
  chainBridgeScene,
  emptyScene,
  groundDef,
  heavyOnLightScene,
  jointsScene,
  MARBLE_RUN_BALLS,
  MARBLE_RUN_CAPSULES,
  MARBLE_RUN_LAYOUT,
  marbleRunScene,
  newtonsCradleScene,
  pileScene,
  pyramidScene,
  rampScene,
  regularPolygon,
  type SceneBlueprint,
  towerScene,
  wreckingBallScene,
} from './scenes.ts'
