/*
 * The page side of the lockstep browser tests: the same LockstepClient the sandbox runs, over the
 * page's own WebSocket, stepped from requestAnimationFrame, with its figures readable through
 * `window.concordLockstep`. Bundled with esbuild and injected into a page served by the test
 * server; the "perturbed" build swaps the engine's own sin for Math.sin (lockstep-harness.ts).
 */

import { sin } from '../../engine/index.ts'
import { findGame } from '../../games/index.ts'
import {
  type ClientMessage,
  decodeServerMessage,
  encodeMessage,
  PROTOCOL_VERSION,
} from '../../shared/index.ts'
import { LockstepClient } from '../../shared/sim/lockstep-client.ts'

/** What the test reads. */
export interface PageReport {
  state: string
  tick: number
  newest: number
  verifiedTick: number
  hashesChecked: number
  desyncs: number
  resyncs: number
  refused: number
  problem: string
  closed: string
}

let client: LockstepClient | null = null
let closed = ''

/** Join `room` on the page's server in lockstep mode as `name` and start stepping. */
function start(room: string, name: string): void {
  const ws = new WebSocket(`${location.origin.replace(/^http/, 'ws')}/ws?room=${room}`)
  ws.binaryType = 'arraybuffer'
  const send = (m: ClientMessage): void => ws.send(encodeMessage(m) as Uint8Array<ArrayBuffer>)
  const runner = new LockstepClient({ games: findGame, send })
  client = runner
  ws.onopen = () => send({ t: 'join', v: PROTOCOL_VERSION, room, name, mode: 'lockstep' })
  ws.onmessage = (event) => {
    const decoded = decodeServerMessage(new Uint8Array(event.data as ArrayBuffer))
    if (decoded.ok) runner.handle(decoded.value, performance.now())
  }
  ws.onclose = (event) => {
    closed = `${event.code} ${event.reason}`
  }
  const frame = (): void => {
    runner.advance(performance.now())
    requestAnimationFrame(frame)
  }
  requestAnimationFrame(frame)
}

/** The runner's figures. */
function report(): PageReport {
  const c = client
  return {
    state: c?.state ?? 'none',
    tick: c?.sim?.tick ?? -1,
    newest: c?.newestTick ?? -1,
    verifiedTick: c?.stats.verifiedTick ?? -1,
    hashesChecked: c?.stats.hashesChecked ?? 0,
    desyncs: c?.stats.desyncs ?? 0,
    resyncs: c?.stats.resyncs ?? 0,
    refused: c?.stats.refused ?? 0,
    problem: c?.lastProblem ?? '',
    closed,
  }
}

/** Angles in [0.1, 3) (step 0.001) where this build's engine sin differs from the page's Math.sin. */
function anglesWhereSinDiffers(own: (x: number) => number): number[] {
  const out: number[] = []
  for (let i = 100; i < 3000 && out.length < 20; i++) {
    const a = i / 1000
    if (own(a) !== Math.sin(a)) out.push(a)
  }
  return out
}

;(globalThis as unknown as { concordLockstep: unknown }).concordLockstep = {
  start,
  report,
  anglesWhereSinDiffers: () => anglesWhereSinDiffers(sin),
}
