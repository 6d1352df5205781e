/*
 * Quantization: positions to integers of 1 mm, angles to integers of 1/65536 turn. The server
 * quantizes once per snapshot; the client dequantizes with the same functions, so both sides agree
 * on every integer and the only error is the rounding here (at most half a quantum).
 */
import { ANGLE_STEPS, POSITION_QUANTUM } from './constants.ts'

const POSITION_SCALE = 1 / POSITION_QUANTUM
const TURN = 2 * Math.PI
/** Largest quantized coordinate magnitude (int32 range). */
const MAX_Q = 2147483647

/** A position (m) as an integer count of POSITION_QUANTUM, clamped to the int32 range (NaN -> 0). */
export function quantizePosition(m: number): number {
  const q = Math.round(m * POSITION_SCALE)
  // NaN fails every comparison: it is sent as 0, never as NaN (the sweep removes such a body).
  if (Number.isNaN(q)) return 0
  return Math.min(MAX_Q, Math.max(-MAX_Q, q))
}

/** A quantized position back to metres. */
export function dequantizePosition(q: number): number {
  return q / POSITION_SCALE
}

/** An angle (rad) as an integer in [0, ANGLE_STEPS): 65536 steps per turn (non-finite -> 0). */
export function quantizeAngle(rad: number): number {
  if (!Number.isFinite(rad)) return 0
  const q = Math.round((rad / TURN) * ANGLE_STEPS) % ANGLE_STEPS
  return q < 0 ? q + ANGLE_STEPS : q
}

/** A quantized angle back to radians in [-pi, pi). */
export function dequantizeAngle(q: number): number {
  const s = q >= ANGLE_STEPS / 2 ? q - ANGLE_STEPS : q
  return (s / ANGLE_STEPS) * TURN
}

/** The shortest signed difference b - a of two quantized angles, in [-32768, 32767]. */
export function angleDelta(a: number, b: number): number {
  let d = (b - a) % ANGLE_STEPS
  if (d >= ANGLE_STEPS / 2) d -= ANGLE_STEPS
  else if (d < -ANGLE_STEPS / 2) d += ANGLE_STEPS
  return d
}

/** A quantized angle plus a signed delta, wrapped into [0, ANGLE_STEPS). */
export function addAngle(a: number, d: number): number {
  const q = (a + d) % ANGLE_STEPS
  return q < 0 ? q + ANGLE_STEPS : q
}

/** Largest error of a dequantized position (m): half a quantum. */
export const MAX_POSITION_ERROR = POSITION_QUANTUM / 2

/** Largest error of a dequantized angle (rad): half a step. */
export const MAX_ANGLE_ERROR = Math.PI / ANGLE_STEPS
