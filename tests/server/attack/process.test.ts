/*
 * The crash attacks of issue 11 against the real server process (server/main.ts in its own Node,
 * as `npm start` runs it): before the fixes, each of these ended the process. After all of them
 * the process is still running and /healthz answers.
 */
import type { ChildProcess } from 'node:child_process'
import { afterAll, describe, expect, it } from 'vitest'
import {
  clientFrame,
  closeOf,
  healthy,
  LONG_NAME_FRAME,
  rawRequest,
  rawWebSocket,
  upgradeRequest,
} from '../../support/raw-client.ts'
import { startServerProcess } from '../../support/server-process.ts'
import { until } from '../../support/wait.ts'

let child: ChildProcess | null = null

afterAll(() => {
  if (child && child.exitCode === null) child.kill('SIGKILL')
})

describe('the server process', { timeout: 30_000 }, () => {
  it('survives every crash attack of the issue and still answers /healthz', async () => {
    const { process: proc, port } = await startServerProcess(['--max-rejects', '20'], {
      DEFAULT_SCENE: 'empty',
      RECORD: 'false',
    })
    child = proc
    const url = `http://127.0.0.1:${port}`
    for (const target of ['//%', '//[']) {
      expect(
        (await rawRequest(port, `GET ${target} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n`)).status,
      ).toBe(400)
      expect((await rawRequest(port, upgradeRequest(target))).status).toBe(400)
    }
    const raw = await rawWebSocket(port, '/ws?room=cut')
    for (let i = 0; i < 20; i++) raw.socket.write(clientFrame(Uint8Array.of(0xc1)))
    raw.socket.write(clientFrame(LONG_NAME_FRAME))
    await until(() => raw.frames.some((f) => f.opcode === 8), 'the close frame')
    expect(closeOf(raw.frames.find((f) => f.opcode === 8)!).code).toBe(1008)
    await raw.closed
    await until(() => healthy(url), '/healthz after the attacks')
    expect(proc.exitCode).toBe(null)
    proc.kill('SIGTERM')
  })
})
