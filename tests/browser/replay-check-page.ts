/*
 * The page side of the Node-versus-Chromium replay check (replay-session.test.ts): the shared
 * headless replay (shared/replay/replay-headless.ts, the code the replay CLI runs) bundled with esbuild
 * for the browser, inflating keyframes with the browser's DecompressionStream.
 */
import { findGame } from '../../games/index.ts'
import { type ReplayReport, replayBytes } from '../../shared/replay/replay-headless.ts'
import { inflate } from '../../shared/sim/sync-payload.ts'

/** Replay a base64-encoded log with --verify, collecting the world hash every `every` ticks. */
export async function replayBase64(base64: string, every: number): Promise<ReplayReport> {
  const text = atob(base64)
  const bytes = new Uint8Array(text.length)
  for (let i = 0; i < text.length; i++) bytes[i] = text.charCodeAt(i)
  return replayBytes(bytes, inflate, findGame, { verify: true, hashEvery: every })
}

/** The handle the test calls through page.evaluate. */
export interface ReplayCheck {
  replayBase64: typeof replayBase64
}

;(globalThis as unknown as { concordReplayCheck: ReplayCheck }).concordReplayCheck = { replayBase64 }
