/*
 * Server settings. Every setting has a default, a command-line flag and an environment variable;
 * a flag beats the environment, which beats the default. Bad values are refused at startup with a
 * message naming the setting, never silently replaced.
 */

import { isIP } from 'node:net'
import { SCENES } from '../../engine/index.ts'
import { ROOM_NAME_PATTERN } from '../../shared/index.ts'
import { checkSecurityConfig } from './config-security.ts'
import { FSYNC_MODES, SETTINGS, type ServerConfig, type Setting } from './config-settings.ts'

export { FSYNC_MODES, SETTINGS, type ServerConfig, type Setting } from './config-settings.ts'

const LOG_LEVELS = ['fatal', 'error', 'warn', 'info', 'debug', 'trace', 'silent']

/** A DNS host name (RFC 1123 labels of letters, digits and inner hyphens), for --host. */
const HOST_NAME =
  /^(?=.{1,253}$)[A-Za-z0-9](?:[A-Za-z0-9-]{0,61}[A-Za-z0-9])?(?:\.[A-Za-z0-9](?:[A-Za-z0-9-]{0,61}[A-Za-z0-9])?)*$/

/** The defaults alone. */
export function defaultConfig(): ServerConfig {
  const config: Record<string, unknown> = {}
  for (const s of SETTINGS) config[s.key] = s.fallback
  return config as unknown as ServerConfig
}

function parseValue(s: Setting, raw: string, source: string): number | string | boolean {
  if (s.kind === 'string') return raw
  if (s.kind === 'bool') {
    if (['1', 'true', 'yes', 'on'].includes(raw)) return true
    if (['0', 'false', 'no', 'off'].includes(raw)) return false
    throw new Error(`${source} must be true or false, got "${raw}"`)
  }
  const n = Number(raw)
  if (
    !/^\d+$/.test(raw) ||
    !Number.isSafeInteger(n) ||
    n < (s.min ?? 0) ||
    n > (s.max ?? Number.MAX_SAFE_INTEGER)
  ) {
    const range = s.max === undefined ? `of at least ${s.min ?? 0}` : `in [${s.min}, ${s.max}]`
    throw new Error(`${source} must be an integer ${range}, got "${raw}"${s.bounds ? `: ${s.bounds}` : ''}`)
  }
  return n
}

/** Settings from flags (`--port 8080` or `--port=8080`), then env, then defaults; throws on bad input. */
export function loadConfig(
  argv: readonly string[],
  env: NodeJS.ProcessEnv,
  overrides: Partial<ServerConfig> = {},
): ServerConfig {
  const config = defaultConfig() as unknown as Record<string, unknown>
  for (const s of SETTINGS) {
    const raw = env[s.env]
    if (raw !== undefined && raw !== '') config[s.key] = parseValue(s, raw, s.env)
  }
  for (let i = 0; i < argv.length; i++) {
    const arg = argv[i]
    const [flag, inline] = arg.includes('=')
      ? [arg.slice(0, arg.indexOf('=')), arg.slice(arg.indexOf('=') + 1)]
      : [arg, undefined]
    const s = SETTINGS.find((x) => x.flag === flag)
    if (!s) throw new Error(`unknown option ${flag} (try --help)`)
    const raw =
      inline ??
      (s.kind === 'bool' && (argv[i + 1] === undefined || argv[i + 1].startsWith('--')) ? 'true' : argv[++i])
    if (raw === undefined) throw new Error(`${flag} needs a value`)
    config[s.key] = parseValue(s, raw, flag)
  }
  Object.assign(config, overrides)
  const result = config as unknown as ServerConfig
  if (60 % result.snapshotRate !== 0)
    throw new Error(`snapshot rate must divide 60, got ${result.snapshotRate}`)
  if (!ROOM_NAME_PATTERN.test(result.defaultRoom)) {
    throw new Error(`default room must be 1-32 letters, digits, "-" or "_", got "${result.defaultRoom}"`)
  }
  if (!Object.hasOwn(SCENES, result.defaultScene)) {
    throw new Error(
      `default scene must be one of ${Object.keys(SCENES).join(', ')}, got "${result.defaultScene}"`,
    )
  }
  if (result.redisUrl !== '' && !/^rediss?:\/\/[^\s]+$/.test(result.redisUrl)) {
    throw new Error(`redis URL must look like redis://HOST:PORT, got "${result.redisUrl}"`)
  }
  if (result.publicUrl !== '' && !/^wss?:\/\/[^\s/?#]+$/.test(result.publicUrl)) {
    throw new Error(`public URL must be ws://HOST:PORT or wss://HOST (no path), got "${result.publicUrl}"`)
  }
  if (isIP(result.host) === 0 && !HOST_NAME.test(result.host)) {
    throw new Error(`host (--host, HOST) must be an IP address or a host name, got "${result.host}"`)
  }
  if (!FSYNC_MODES.includes(result.replayFsync)) {
    throw new Error(`replay fsync must be one of ${FSYNC_MODES.join(', ')}, got "${result.replayFsync}"`)
  }
  if (!LOG_LEVELS.includes(result.logLevel)) {
    throw new Error(`log level must be one of ${LOG_LEVELS.join(', ')}, got "${result.logLevel}"`)
  }
  checkSecurityConfig(result)
  return result
}

/** The settings as a help text table. */
export function helpText(): string {
  const table = [
    ['flag', 'env', 'default', 'meaning'],
    ...SETTINGS.map((s) => [`${s.flag} <${s.kind}>`, s.env, s.shown ?? String(s.fallback), s.help]),
  ]
  // Each column as wide as its longest cell, so every row lines up.
  const widths = [0, 1, 2].map((c) => Math.max(...table.map((row) => row[c].length)))
  const rows = table.map(
    (row) =>
      `  ${row[0].padEnd(widths[0])}  ${row[1].padEnd(widths[1])}  ${row[2].padEnd(widths[2])}  ${row[3]}`,
  )
  return [
    'Usage: npm start -- [options]   (or: node dist/server.js [options])',
    '',
    ...rows.map((r) => r.trimEnd()),
  ].join('\n')
}

/** The line a person at a terminal sees: where to open the sandbox (any-address hosts as 127.0.0.1). */
export function sandboxBanner(host: string, port: number): string {
  const all = host === '0.0.0.0' || host === '::' || host === ''
  const shown = all ? '127.0.0.1' : host.includes(':') ? `[${host}]` : host
  return `Concord sandbox at http://${shown}:${port}/${all ? ` (listening on every address, ${host || '0.0.0.0'})` : ''}`
}

/** Unsent bytes at which a client is dropped at once: 8 send-buffer budgets, at least 1 MiB. */
export function hardBufferLimit(config: ServerConfig): number {
  return Math.max(config.sendBufferBytes * 8, 1 << 20)
}
