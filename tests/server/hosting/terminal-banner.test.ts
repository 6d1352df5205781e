/*
 * `npm start` on a terminal (issue 31, fix 11): besides the JSON log, the server prints where to
 * open the sandbox, "Concord sandbox at http://127.0.0.1:PORT/", with the port it bound. Run under
 * a real pseudo-terminal (util-linux `script`), and with stdout a pipe, where the line is left out
 * so the log stays pure JSON for collectors.
 */
import { type ChildProcess, spawn } from 'node:child_process'
import { afterEach, describe, expect, it } from 'vitest'
import { sandboxBanner } from '../../../server/config/config.ts'
import { until } from '../../support/wait.ts'

const SERVER = 'node --import tsx server/main.ts --port 0 --record false --recover false'
let proc: ChildProcess | null = null

afterEach(() => {
  if (proc && proc.exitCode === null) proc.kill('SIGKILL')
  proc = null
})

/** Start `command` and collect its stdout. */
function start(command: string, args: string[]): { out: () => string } {
  let text = ''
  proc = spawn(command, args, { stdio: ['ignore', 'pipe', 'inherit'] })
  proc.stdout!.on('data', (c: Buffer) => {
    text += c.toString('utf8')
  })
  return { out: () => text }
}

const listeningPort = (text: string): number | null => {
  const m = /"msg":"listening"[^\n]*"port":(\d+)|"port":(\d+)[^\n]*"msg":"listening"/.exec(text)
  return m ? Number(m[1] ?? m[2]) : null
}

describe('the address on a terminal', { timeout: 60_000 }, () => {
  it('prints "Concord sandbox at http://127.0.0.1:PORT/" with the bound port when stdout is a TTY', async () => {
    // script(1) gives the server a pseudo-terminal as stdout (-e: its exit status, -q: no banner).
    const server = start('script', ['-qfec', SERVER, '/dev/null'])
    await until(
      () => /Concord sandbox at /.test(server.out()) && listeningPort(server.out()) !== null,
      'the banner and the listening line',
      50_000,
    )
    const port = listeningPort(server.out())
    expect(server.out()).toContain(`Concord sandbox at http://127.0.0.1:${port}/\r\n`)
    expect((await fetch(`http://127.0.0.1:${port}/healthz`)).status).toBe(200)
  })

  it('leaves the line out when stdout is a pipe: every line is JSON', async () => {
    const server = start(process.execPath, ['--import', 'tsx', ...SERVER.split(' ').slice(3)])
    await until(() => listeningPort(server.out()) !== null, 'the listening line', 50_000)
    const lines = server
      .out()
      .split('\n')
      .filter((l) => l !== '')
    for (const line of lines) expect(() => JSON.parse(line), line).not.toThrow()
  })

  it('names 127.0.0.1 for a server on every address, and brackets an IPv6 host', () => {
    expect(sandboxBanner('127.0.0.1', 8080)).toBe('Concord sandbox at http://127.0.0.1:8080/')
    expect(sandboxBanner('0.0.0.0', 80)).toBe(
      'Concord sandbox at http://127.0.0.1:80/ (listening on every address, 0.0.0.0)',
    )
    expect(sandboxBanner('::1', 9000)).toBe('Concord sandbox at http://[::1]:9000/')
  })
})
