/*
 * The image, the Agones fleet and the Kubernetes Deployment record (issue 30, point 7), checked
 * statically (no Docker engine or cluster runs here): the runtime stage makes the default replay
 * directory, resolved against its WORKDIR, belong to the uid:gid it runs as, before declaring it a
 * VOLUME (Docker drops changes to a volume's path made after the declaration), and nothing moves
 * --replay-dir elsewhere; both manifests mount a volume at that path, writable by that group, and
 * ask for recording to be required. The server side (a directory that cannot be written is said
 * loudly and fails /readyz) is tests/server/replay/recording-required.test.ts.
 */
import { readFileSync } from 'node:fs'
import { posix } from 'node:path'
import { describe, expect, it } from 'vitest'
import { loadConfig } from '../../server/config/config.ts'
import { envPairs, execForm, readDockerfile } from './dockerfile.ts'

const runtime = readDockerfile('docker/Dockerfile').at(-1)!
const steps = runtime.instructions
const workdir = steps.filter((s) => s.op === 'WORKDIR').at(-1)?.args ?? '/'
const env = Object.fromEntries(steps.filter((s) => s.op === 'ENV').flatMap((s) => envPairs(s.args)))
/** The replay directory the image's server writes: the setting as its ENV leaves it, under WORKDIR. */
const replayDir = posix.resolve(workdir, loadConfig([], env).replayDir)
const user = steps.filter((s) => s.op === 'USER').at(-1)?.args ?? 'root'

/** The mounts of `manifest`: [volume name, mountPath] pairs, and its volumes' names (no YAML library). */
function mounts(manifest: string): { mounts: Array<[string, string]>; volumes: string[]; text: string } {
  const text = readFileSync(manifest, 'utf8')
  const lines = text.split('\n')
  const found: Array<[string, string]> = []
  const volumes: string[] = []
  let section = ''
  for (let i = 0; i < lines.length; i++) {
    const key = /^\s*(volumeMounts|volumes):\s*$/.exec(lines[i])
    if (key) section = key[1]
    else if (/^\s*[a-zA-Z]+:/.test(lines[i]) && !/^\s*(- name|mountPath|emptyDir|name):/.test(lines[i]))
      section = ''
    const name = /^\s*- name: (\S+)\s*$/.exec(lines[i])
    if (!name) continue
    if (section === 'volumes') volumes.push(name[1])
    const path = /^\s*mountPath: (\S+)\s*$/.exec(lines[i + 1] ?? '')
    if (section === 'volumeMounts' && path) found.push([name[1], path[1]])
  }
  return { mounts: found, volumes, text }
}

describe('the image records', () => {
  it('makes the replay directory belong to its user before declaring it a VOLUME', () => {
    expect(replayDir).toBe('/app/replays')
    const [uid, gid = uid] = user.split(':')
    expect(uid).toMatch(/^[1-9]\d*$/)
    const made = steps.findIndex(
      (s) =>
        s.op === 'RUN' &&
        s.args.includes('mkdir -p') &&
        new RegExp(`chown ${uid}:${gid} (\\S+ )*(replays|${replayDir})( |$)`).test(s.args),
    )
    expect(made, 'a RUN that creates the replay directory and gives it to the USER').toBeGreaterThanOrEqual(0)
    // The RUN works relative to WORKDIR (the image test replays it outside Docker).
    expect(steps[made].args).not.toContain('/app')
    const volume = steps.findIndex((s) => s.op === 'VOLUME')
    expect(volume).toBeGreaterThan(made)
    expect(execForm(steps[volume].args)).toEqual([replayDir])
    expect(steps.findIndex((s) => s.op === 'USER')).toBeGreaterThan(made)
  })
})

describe('the manifests record', () => {
  it('docker/compose.yaml keeps the replay directory in a named volume', () => {
    const text = readFileSync('docker/compose.yaml', 'utf8')
    const mount = /^\s*- (\w+):(\S+)\s*$/m.exec(text)
    expect(mount?.[2]).toBe(replayDir)
    expect(text).toMatch(new RegExp(`^volumes:\\n  ${mount?.[1]}:`, 'm'))
  })

  for (const manifest of ['docker/agones/fleet.yaml', 'docker/k8s/deployment.yaml']) {
    it(`${manifest} mounts a volume at the replay directory, writable by the server's group, and requires recording`, () => {
      const m = mounts(manifest)
      const mount = m.mounts.find(([, path]) => path === replayDir)
      expect(mount, `a volumeMount at ${replayDir}`).toBeDefined()
      expect(m.volumes).toContain(mount![0])
      expect(m.text).toMatch(/runAsUser: 1000\s/)
      expect(m.text).toMatch(/fsGroup: 1000\s/)
      expect(m.text).toMatch(/- name: REQUIRE_RECORDING\s+value: "true"/)
    })
  }
})
