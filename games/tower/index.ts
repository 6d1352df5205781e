/*
 * Tower: the building race (docs/games.md, "Tower"): each player drops blocks on their own
 * platform with `block`; the game measures the towers every tick; fallen blocks cost; the best
 * score when the round's time is up wins.
 */

export { metres, type TowerView, towerClient } from './tower-client.ts'
export {
  BLOCKS,
  DROP_CLEARANCE,
  DROP_COOLDOWN,
  FALL_LINE,
  FALL_PENALTY,
  LANE_SPACING,
  LANES,
  laneX,
  PLATFORM_HALF_WIDTH,
  ROUND_TICKS,
  SETTLED_SPEED,
  type TowerBlock,
  type TowerState,
  tower,
  towerScore,
} from './tower-game.ts'
