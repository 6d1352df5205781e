/*
 * docker/k8s/deployment.yaml's environment, read as the server reads it: every variable is a real
 * setting whose value the server accepts (a typo would be silently ignored by Kubernetes and by
 * the server), and the per-address limits are off, as the README's Kubernetes section promises
 * (behind an ingress every player may carry the proxy's address). No YAML library: the manifest's
 * env entries are `- name: X` lines each followed by `value: Y`.
 */
import { readFileSync } from 'node:fs'
import { describe, expect, it } from 'vitest'
import { loadConfig } from '../../server/config/config.ts'
import { SETTINGS } from '../../server/config/config-settings.ts'

/** The container's env entries, in order. */
function manifestEnv(): Array<[string, string]> {
  const lines = readFileSync('docker/k8s/deployment.yaml', 'utf8').split('\n')
  const env: Array<[string, string]> = []
  for (let i = 0; i < lines.length; i++) {
    const name = /^\s*- name: ([A-Z_]+)\s*$/.exec(lines[i])
    const value = name ? /^\s*value: "?([^"]*)"?\s*$/.exec(lines[i + 1] ?? '') : null
    if (name && value) env.push([name[1], value[1]])
  }
  return env
}

describe('the Kubernetes Deployment', () => {
  it('sets only real settings, to values the server accepts', () => {
    const env = manifestEnv()
    expect(env.length).toBeGreaterThanOrEqual(6)
    const known = new Set(SETTINGS.map((s) => s.env))
    for (const [name] of env) expect(known.has(name), `${name} is a setting`).toBe(true)
    const config = loadConfig([], Object.fromEntries(env))
    expect(config.host).toBe('0.0.0.0')
    expect(config.port).toBe(8080)
    expect(config.workers).toBe(1)
  })

  it('turns the per-address limits off, as the README says', () => {
    const config = loadConfig([], Object.fromEntries(manifestEnv()))
    expect(config.maxConnectionsPerIp).toBe(0)
    expect(config.maxRequestsPerIp).toBe(0)
    expect(config.maxNewRoomsPerIp).toBe(0)
    expect(readFileSync('README.md', 'utf8')).toContain('`MAX_CONNECTIONS_PER_IP=0`, `MAX_REQUESTS_PER_IP=0`')
  })
})
