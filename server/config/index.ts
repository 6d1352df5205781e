/*
 * Server settings: one table of every setting (flag, environment variable, default, help) in
 * config-settings.ts, read by config.ts (loading and checks) and config-security.ts (the limits).
 */

export {
  hardBufferLimit,
  helpText,
  loadConfig,
  SETTINGS,
  type ServerConfig,
  sandboxBanner,
} from './config.ts'
export { listSetting } from './config-security.ts'
