/*
 * The scenes a user can pick by name (the sandbox's `scene` command, PROTOCOL.md's Scenes table),
 * each with the parameters the sandbox uses.
 */
import { machinesScene } from './machine-scenes.ts'
import { playgroundScene } from './playground-scene.ts'
import {
  cardHouseScene,
  chainBridgeScene,
  emptyScene,
  heavyOnLightScene,
  jointsScene,
  marbleRunScene,
  newtonsCradleScene,
  pileScene,
  pyramidScene,
  rampScene,
  type SceneBlueprint,
  towerScene,
  wreckingBallScene,
} from './scenes.ts'

/** The scene a new room and the offline page start with when none is named (issue 31). */
export const DEFAULT_SCENE = 'playground'

/** Scenes a user can pick by name, with the parameters the sandbox uses. */
export const SCENES: Readonly<Record<string, { description: string; make: () => SceneBlueprint }>> = {
  empty: { description: 'Only the ground', make: emptyScene },
  pyramid: { description: 'A 20-row pyramid of 210 boxes', make: () => pyramidScene(20) },
  playground: {
    description: 'Ready-made machines to play with: a car, a seesaw, a lift, a windmill',
    make: playgroundScene,
  },
  pile: { description: '300 mixed shapes in a container', make: () => pileScene(300) },
  'pile-1000': { description: '1,000 mixed shapes in a container', make: () => pileScene(1000) },
  tower: { description: 'A staggered tower of 20 boxes', make: () => towerScene(20, true) },
  ramp: { description: 'A box resting on a 20 degree ramp', make: () => rampScene() },
  'heavy-on-light': { description: 'A 400:1 mass ratio stack', make: heavyOnLightScene },
  joints: {
    description: 'A motor-driven paddle, a hinged arm stopping at its limits, a ball on a spring',
    make: jointsScene,
  },
  'wrecking-ball': {
    description: 'A heavy ball on a rope swings into a tower of boxes',
    make: wreckingBallScene,
  },
  'newtons-cradle': { description: "Newton's cradle: five elastic balls on rods", make: newtonsCradleScene },
  'chain-bridge': {
    description: 'A bridge of 20 planks pinned end to end, with boxes dropped on it',
    make: chainBridgeScene,
  },
  'card-house': { description: 'A five-storey house of leaning cards', make: cardHouseScene },
  'marble-run': {
    description: 'Balls and capsules run down four chain tracks into a bin whose sensor counts them',
    make: marbleRunScene,
  },
  machines: {
    description: 'A car on bumps, a piston, a welded crane, a bridge that breaks, a driven platform',
    make: machinesScene,
  },
}
