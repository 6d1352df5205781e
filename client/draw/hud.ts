/*
 * The HUD: one block of monospace text, refreshed a few times a second (not every frame, so it
 * costs nothing and stays readable). Numbers a mode does not have are shown as "-".
 */
import type { SandboxStats } from '../modes/index.ts'

const n = (v: number | null, digits = 0, unit = ''): string =>
  v === null ? '-' : `${v.toFixed(digits)}${unit}`

/** Longest room name the HUD shows whole (a valid name has at most 32 characters). */
const ROOM_SHOWN = 32

/** A room name as the HUD shows it: cut to ROOM_SHOWN characters with an ellipsis. */
export function shownRoom(room: string): string {
  return room.length > ROOM_SHOWN ? `${room.slice(0, ROOM_SHOWN - 1)}…` : room
}

/** The HUD text for one refresh. */
export function hudText(
  s: SandboxStats,
  fps: number,
  mode: 'online' | 'offline' | 'replay',
  scene: string,
): string {
  const lines = [
    `${mode === 'offline' ? 'offline' : `${mode === 'replay' ? 'replay of' : 'room'} ${shownRoom(s.room)}`}  ${scene}  players ${s.players}`,
    `tick ${s.tick}  fps ${fps.toFixed(0)}`,
    `bodies ${s.awake} awake / ${s.total}`,
  ]
  if (mode === 'online') {
    lines.push(`ping ${n(s.pingMs, 0, ' ms')}  delay ${n(s.delayMs, 0, ' ms')}`)
    lines.push(`snapshots ${n(s.snapshotHz, 0, ' Hz')}`)
    lines.push(`down ${n(s.downKBs, 1, ' kB/s')}  up ${n(s.upKBs, 1, ' kB/s')}`)
  }
  const l = s.lockstep
  if (l) {
    lines.push(`${l.mode} ${l.state}  verified tick ${l.verifiedTick}`)
    lines.push(`desyncs ${l.desyncs}  resyncs ${l.resyncs}`)
    if (l.mode === 'predict')
      lines.push(
        `rollbacks ${n(l.rollbacksPerSecond, 0, '/s')}  depth ${n(l.rollbackDepth)}  resim ${n(l.resimMs, 2, ' ms')}`,
      )
  }
  lines.push(mode === 'online' ? `server tick ${n(s.stepMs, 2, ' ms')}` : `step ${n(s.stepMs, 2, ' ms')}`)
  return lines.join('\n')
}

/** Counts frames and reports frames per second over the last half second or more. */
export class FpsMeter {
  private frames = 0
  private start = Number.NaN
  value = 0

  /** Count one frame at `nowMs`. */
  frame(nowMs: number): void {
    if (Number.isNaN(this.start)) this.start = nowMs
    this.frames++
    const elapsed = nowMs - this.start
    if (elapsed >= 500) {
      this.value = (this.frames * 1000) / elapsed
      this.frames = 0
      this.start = nowMs
    }
  }
}
