/*
 * The image's own install and start commands, replayed outside Docker (no Docker engine runs on
 * the development machines). The test reads docker/Dockerfile and follows it step by step in two
 * clean temporary directories standing in for the two stages' /app:
 *   build stage:   its COPY lines (`.` = the files git tracks, as .dockerignore leaves them) and
 *                  its RUN lines, except `npm ci` itself: the build directory links the
 *                  repository's node_modules instead, installed by `npm ci` from the same lock file
 *   runtime stage: every COPY (dist/ from the build directory), every RUN exactly as written
 *                  (`npm ci --omit=dev ...`, cache mount flags dropped), the ENV, then the CMD and
 *                  the HEALTHCHECK command.
 * It checks that only production packages were installed, that the started server answers
 * /healthz, /readyz, the client page and a WebSocket join, that the HEALTHCHECK command passes
 * (and fails once the server is gone), and that SIGTERM to the CMD process drains and exits 0.
 * Not covered: the base image, the USER switch (checked to be a numeric non-root uid only), and
 * Docker's own build cache and layer handling.
 */
import { type ChildProcess, execFileSync, spawn } from 'node:child_process'
import { cpSync, existsSync, mkdirSync, mkdtempSync, rmSync, symlinkSync } from 'node:fs'
import { createServer } from 'node:net'
import { tmpdir } from 'node:os'
import { dirname, join, resolve } from 'node:path'
import { createInterface } from 'node:readline'
import { afterAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../bots/bot-client.ts'
import { envPairs, execForm, type Instruction, readDockerfile, splitFlags } from './dockerfile.ts'

const REPO = resolve('.')
const work = mkdtempSync(join(tmpdir(), 'concord-image-'))
const buildDir = join(work, 'build')
const appDir = join(work, 'app')
let server: ChildProcess | null = null

afterAll(() => {
  if (server && server.exitCode === null) server.kill('SIGKILL')
  rmSync(work, { recursive: true, force: true })
})

function trackedFiles(): string[] {
  return execFileSync('git', ['ls-files', '-z', '--cached', '--others', '--exclude-standard'], {
    cwd: REPO,
    encoding: 'utf8',
  })
    .split('\0')
    .filter((f) => f !== '' && existsSync(join(REPO, f)))
}

/** COPY sources... dest, relative to `from` (the repository or another stage's directory). */
function replayCopy(args: string, into: string, stageDirs: Map<string, string>): void {
  const { flags, rest } = splitFlags(args)
  const parts = rest.split(/\s+/)
  const dest = resolve(into, parts.pop() ?? '.')
  const fromStage = flags.get('from')
  for (const source of parts) {
    if (fromStage !== undefined) {
      const stageDir = stageDirs.get(fromStage)
      if (!stageDir) throw new Error(`COPY --from=${fromStage}: no such stage`)
      cpSync(join(stageDir, source.replace(/^\/app\/?/, '')), dest, { recursive: true })
    } else if (source === '.') {
      for (const file of trackedFiles()) {
        mkdirSync(dirname(join(dest, file)), { recursive: true })
        cpSync(join(REPO, file), join(dest, file))
      }
    } else {
      mkdirSync(dest, { recursive: true })
      cpSync(join(REPO, source), join(dest, source))
    }
  }
}

function run(command: string, cwd: string, env: NodeJS.ProcessEnv): void {
  execFileSync('sh', ['-c', command], { cwd, env, stdio: ['ignore', 'ignore', 'pipe'], timeout: 300_000 })
}

function freePort(): Promise<number> {
  return new Promise((done) => {
    const probe = createServer().listen(0, '127.0.0.1', () => {
      const address = probe.address()
      const port = typeof address === 'object' && address ? address.port : 0
      probe.close(() => done(port))
    })
  })
}

const stages = readDockerfile('docker/Dockerfile')
const buildStage = stages.find((s) => s.name === 'build')
const runtime = stages[stages.length - 1]
const only = (ops: string, list: Instruction[]) => list.filter((i) => i.op === ops)

describe('docker/Dockerfile replayed in clean directories', { timeout: 300_000 }, () => {
  it('has a build stage and a runtime stage on the same Node major', () => {
    expect(buildStage).toBeDefined()
    expect(runtime.name).not.toBe('build')
    expect(runtime.image).toMatch(/^node:20/)
  })

  it('the runtime stage installs production packages only, runs as a numeric non-root user and listens on 0.0.0.0', async () => {
    mkdirSync(buildDir)
    mkdirSync(appDir)
    const stageDirs = new Map([['build', buildDir]])
    const baseEnv = { PATH: process.env.PATH, HOME: process.env.HOME ?? work }
    for (const step of buildStage?.instructions ?? []) {
      if (step.op === 'COPY') replayCopy(step.args, buildDir, stageDirs)
      else if (step.op === 'RUN' && /^npm ci(\s|$)/.test(step.args))
        symlinkSync(join(REPO, 'node_modules'), join(buildDir, 'node_modules'))
      else if (step.op === 'RUN') run(step.args, buildDir, baseEnv)
    }
    expect(existsSync(join(buildDir, 'dist/server.js'))).toBe(true)
    const env: Record<string, string> = {}
    for (const step of runtime.instructions) {
      if (step.op === 'COPY') replayCopy(step.args, appDir, stageDirs)
      if (step.op === 'RUN') run(splitFlags(step.args).rest, appDir, { ...baseEnv, ...env })
      if (step.op === 'ENV') for (const [k, v] of envPairs(step.args)) env[k] = v
    }
    for (const pkg of ['ws', 'msgpackr', 'pino', 'prom-client'])
      expect(existsSync(join(appDir, 'node_modules', pkg, 'package.json')), pkg).toBe(true)
    for (const dev of ['vitest', 'esbuild', 'typescript', 'playwright-core', 'tsx'])
      expect(existsSync(join(appDir, 'node_modules', dev)), dev).toBe(false)
    expect(existsSync(join(appDir, 'engine')), 'sources stay in the build stage').toBe(false)
    expect(env.HOST).toBe('0.0.0.0')
    expect(env.NODE_ENV).toBe('production')
    const user = only('USER', runtime.instructions).at(-1)?.args ?? 'root'
    expect(user).toMatch(/^[1-9]\d*(:\d+)?$/)
  })

  it('the CMD serves /healthz, /readyz, the client and a join; HEALTHCHECK passes; SIGTERM drains and exits 0', async () => {
    const env: Record<string, string> = {}
    for (const step of only('ENV', runtime.instructions)) for (const [k, v] of envPairs(step.args)) env[k] = v
    const port = await freePort()
    const processEnv = { PATH: process.env.PATH ?? '', HOME: work, ...env, PORT: String(port) }
    const cmd = execForm(only('CMD', runtime.instructions).at(-1)?.args ?? '[]')
    const health = only('HEALTHCHECK', runtime.instructions).at(-1)
    const healthCmd = execForm(splitFlags(health?.args ?? '').rest.replace(/^CMD\s+/, ''))
    const proc = spawn(cmd[0], cmd.slice(1), {
      cwd: appDir,
      env: processEnv,
      stdio: ['ignore', 'pipe', 'pipe'],
    })
    server = proc
    let stderr = ''
    proc.stderr?.on('data', (d) => {
      stderr += d
    })
    await new Promise<void>((done, fail) => {
      proc.once('exit', (code) => fail(new Error(`server exited early with ${code}: ${stderr}`)))
      createInterface({ input: proc.stdout! }).on('line', (line) => {
        if (line.includes('"msg":"listening"')) done()
      })
    })
    const base = `http://127.0.0.1:${port}`
    expect((await fetch(`${base}/healthz`)).status).toBe(200)
    expect((await fetch(`${base}/readyz`)).status).toBe(200)
    const page = await fetch(`${base}/`)
    expect(page.status).toBe(200)
    expect(await page.text()).toContain('<html')
    const bot = await BotClient.connect({ url: base, room: 'lobby', name: 'docker' })
    expect(bot.received.some((m) => m.t === 'welcome')).toBe(true)
    const check = (): number => {
      try {
        execFileSync(healthCmd[0], healthCmd.slice(1), { cwd: appDir, env: processEnv, stdio: 'ignore' })
        return 0
      } catch (error) {
        return (error as { status?: number }).status ?? -1
      }
    }
    expect(check()).toBe(0)
    proc.removeAllListeners('exit')
    const exited = new Promise<number | null>((done) => proc.once('exit', (code) => done(code)))
    proc.kill('SIGTERM')
    expect(await exited).toBe(0)
    await bot.closed
    expect(bot.closeCode).toBe(1001)
    expect(check()).toBe(1)
  })
})
