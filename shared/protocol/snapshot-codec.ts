/*
 * The snapshot payload (`data` in a `snap` message), a byte string read front to back:
 *
 *   varint  n                      number of body updates, ids ascending
 *   n times:
 *     varint  head                 (id - previous id) * 4 + flags; previous id starts at 0
 *                                  flags bit 0: absolute (the baseline lacks this body)
 *                                  flags bit 1: awake
 *     zigzag  x, y                 absolute: quantized position (mm)
 *                                  else: difference from the baseline's value
 *     zigzag  a                    absolute: quantized angle in [0, 65536)
 *                                  else: shortest wrapped difference in [-32768, 32767]
 *
 * The client's state at the snapshot's tick is its state at the baseline tick with these updates
 * applied; bodies not listed are unchanged. A moving body costs about 6-7 bytes; a resting one
 * nothing. Deltas (Fiedler, "Snapshot Compression") keep the numbers small; the varints keep small
 * numbers short.
 */
import { ByteReader, type ByteWriter, varintSize, zigzagSize } from './byte-io.ts'
import { addAngle, angleDelta } from './quantize.ts'
import { FRAME_AWAKE, FRAME_PRESENT, type QuantizedFrame } from './quantized-frame.ts'

/** Head flag: the update holds absolute values. */
export const UPDATE_ABSOLUTE = 1
/** Head flag: the body is awake. */
export const UPDATE_AWAKE = 2

/** Upper bound on an update's size in bytes, given the frames (the head assumes a full id). */
export function updateSize(frame: QuantizedFrame, base: QuantizedFrame, id: number): number {
  const head = varintSize(id * 4 + 3)
  if (!base.has(id)) return head + zigzagSize(frame.x[id]) + zigzagSize(frame.y[id]) + zigzagSize(frame.a[id])
  return (
    head +
    zigzagSize(frame.x[id] - base.x[id]) +
    zigzagSize(frame.y[id] - base.y[id]) +
    zigzagSize(angleDelta(base.a[id], frame.a[id]))
  )
}

/** Write the updates for `ids` (ascending) of `frame` relative to `base`. */
export function writeUpdates(
  out: ByteWriter,
  frame: QuantizedFrame,
  base: QuantizedFrame,
  ids: ArrayLike<number>,
  count: number,
): void {
  out.writeVarint(count)
  let previous = 0
  for (let i = 0; i < count; i++) {
    const id = ids[i]
    const absolute = !base.has(id)
    const awake = (frame.flags[id] & FRAME_AWAKE) !== 0
    out.writeVarint((id - previous) * 4 + (absolute ? UPDATE_ABSOLUTE : 0) + (awake ? UPDATE_AWAKE : 0))
    previous = id
    if (absolute) {
      out.writeZigzag(frame.x[id])
      out.writeZigzag(frame.y[id])
      out.writeZigzag(frame.a[id])
    } else {
      out.writeZigzag(frame.x[id] - base.x[id])
      out.writeZigzag(frame.y[id] - base.y[id])
      out.writeZigzag(angleDelta(base.a[id], frame.a[id]))
    }
  }
}

/**
 * Read a payload: `out` becomes `base` with the updates applied. Returns the updated ids in order.
 * Throws RangeError on truncated or inconsistent data (a delta for a body the baseline lacks).
 */
export function readUpdates(data: Uint8Array, base: QuantizedFrame, out: QuantizedFrame): number[] {
  const reader = new ByteReader(data)
  out.copyFrom(base)
  const n = reader.readVarint()
  if (n > data.length) throw new RangeError(`snapshot claims ${n} updates in ${data.length} bytes`)
  const updated: number[] = []
  let id = 0
  for (let i = 0; i < n; i++) {
    const head = reader.readVarint()
    const flags = head % 4
    const step = (head - flags) / 4
    if (step < 1) throw new RangeError('snapshot ids must ascend')
    id += step
    const dx = reader.readZigzag()
    const dy = reader.readZigzag()
    const da = reader.readZigzag()
    const awake = (flags & UPDATE_AWAKE) !== 0
    if (flags & UPDATE_ABSOLUTE) {
      if (da < 0 || da >= 65536) throw new RangeError(`absolute angle ${da} out of range`)
      out.put(id, dx, dy, da, awake)
    } else {
      if (!base.has(id)) throw new RangeError(`delta for body ${id} missing from the baseline`)
      out.put(id, base.x[id] + dx, base.y[id] + dy, addAngle(base.a[id], da), awake)
    }
    updated.push(id)
  }
  if (!reader.done) throw new RangeError('trailing bytes after snapshot updates')
  return updated
}

/** Flags value of a present, awake/asleep body (for tests). */
export function frameFlags(awake: boolean): number {
  return FRAME_PRESENT | (awake ? FRAME_AWAKE : 0)
}
