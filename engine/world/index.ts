/*
 * The World: its storage (world-store.ts), its public methods (world-api.ts), its queries
 * (query-api.ts, over engine/queries), the step as a list of stages (world.ts), its contact and sensor events (events.ts) and the sensor stage (sensor.ts),
 * and saving, loading and hashing (world-state.ts, save-format.ts).
 */

export type {
  ContactEvents,
  ContactHitEvent,
  ContactTouchEvent,
  SensorEvent,
  SensorEvents,
} from './events.ts'
export { MAX_QUERY_TRANSLATION, type QueryFilterDef, type QueryTransform } from './query-api.ts'
export { SAVE_FORMAT_VERSION, WorldLoadError } from './save-format.ts'
export { createWorld, loadWorld, World } from './world.ts'
export {
  POSE_ANGLE,
  POSE_AWAKE,
  POSE_ID,
  POSE_STATIC,
  POSE_STRIDE,
  POSE_TYPE,
  POSE_X,
  POSE_Y,
} from './world-api.ts'
export { DEFAULT_WORLD_DEF, resolveWorldDef } from './world-store.ts'
