/*
 * A quantized frame: the moving bodies' quantized poses at one tick, in columns indexed by body id
 * (ids are small dense integers within a world epoch, so an array beats a Map here). The server
 * builds one frame per snapshot tick and shares it across clients; each client's acknowledged
 * baseline is a frame too, on both ends of the socket.
 */

/** Flag bit: the body exists in this frame. */
export const FRAME_PRESENT = 1
/** Flag bit: the body is awake. */
export const FRAME_AWAKE = 2

/** Quantized poses of the moving bodies at one tick, indexed by body id. */
export class QuantizedFrame {
  /** Quantized x (mm). */
  x: Int32Array
  /** Quantized y (mm). */
  y: Int32Array
  /** Quantized angle (1/65536 turn). */
  a: Int32Array
  /** FRAME_PRESENT | FRAME_AWAKE bits. */
  flags: Uint8Array
  /** Present ids, ascending, in ids[0 .. count). */
  ids: Int32Array
  count = 0

  constructor(capacity = 64) {
    this.x = new Int32Array(capacity)
    this.y = new Int32Array(capacity)
    this.a = new Int32Array(capacity)
    this.flags = new Uint8Array(capacity)
    this.ids = new Int32Array(capacity)
  }

  /** Capacity in ids (largest id + 1 that fits without growing). */
  get capacity(): number {
    return this.flags.length
  }

  /** Grow the columns so that `id` fits. */
  ensure(id: number): void {
    if (id >= this.flags.length) this.grow(id)
  }

  /**
   * The slow path of ensure, a method of its own: a closure inside ensure would make V8 allocate
   * its context on every call, even when nothing grows (about 40 bytes per put).
   */
  private grow(id: number): void {
    let size = this.flags.length
    while (size <= id) size *= 2
    const x = new Int32Array(size)
    const y = new Int32Array(size)
    const a = new Int32Array(size)
    const flags = new Uint8Array(size)
    x.set(this.x)
    y.set(this.y)
    a.set(this.a)
    flags.set(this.flags)
    this.x = x
    this.y = y
    this.a = a
    this.flags = flags
  }

  /** Remove every body. */
  clear(): void {
    for (let i = 0; i < this.count; i++) this.flags[this.ids[i]] = 0
    this.count = 0
  }

  /** True if the body is in the frame. */
  has(id: number): boolean {
    return id < this.flags.length && (this.flags[id] & FRAME_PRESENT) !== 0
  }

  /** Set a body's quantized pose; ids must be added in ascending order after clear(). */
  put(id: number, x: number, y: number, a: number, awake: boolean): void {
    this.ensure(id)
    if ((this.flags[id] & FRAME_PRESENT) === 0) this.addId(id)
    this.x[id] = x
    this.y[id] = y
    this.a[id] = a
    this.flags[id] = FRAME_PRESENT | (awake ? FRAME_AWAKE : 0)
  }

  private addId(id: number): void {
    if (this.count === this.ids.length) {
      const ids = new Int32Array(this.ids.length * 2)
      ids.set(this.ids)
      this.ids = ids
    }
    // Keep ids ascending: append, then bubble into place (appends are ascending in practice).
    let i = this.count++
    while (i > 0 && this.ids[i - 1] > id) {
      this.ids[i] = this.ids[i - 1]
      i--
    }
    this.ids[i] = id
  }

  /** Remove one body. */
  remove(id: number): void {
    if (!this.has(id)) return
    this.flags[id] = 0
    let j = 0
    for (let i = 0; i < this.count; i++) if (this.ids[i] !== id) this.ids[j++] = this.ids[i]
    this.count = j
  }

  /** Make this frame an exact copy of `other`. */
  copyFrom(other: QuantizedFrame): void {
    this.clear()
    this.ensure(other.capacity - 1)
    if (this.ids.length < other.ids.length) this.ids = new Int32Array(other.ids.length)
    for (let i = 0; i < other.count; i++) {
      const id = other.ids[i]
      this.x[id] = other.x[id]
      this.y[id] = other.y[id]
      this.a[id] = other.a[id]
      this.flags[id] = other.flags[id]
      this.ids[i] = id
    }
    this.count = other.count
  }

  /** True if both frames hold the same bodies with the same poses and awake bits. */
  equals(other: QuantizedFrame): boolean {
    if (this.count !== other.count) return false
    for (let i = 0; i < this.count; i++) {
      const id = this.ids[i]
      if (
        other.ids[i] !== id ||
        this.x[id] !== other.x[id] ||
        this.y[id] !== other.y[id] ||
        this.a[id] !== other.a[id] ||
        this.flags[id] !== other.flags[id]
      )
        return false
    }
    return true
  }

  /** True if the body's pose and awake bit equal those in `other` (both must have it). */
  sameAs(other: QuantizedFrame, id: number): boolean {
    return (
      other.has(id) &&
      this.x[id] === other.x[id] &&
      this.y[id] === other.y[id] &&
      this.a[id] === other.a[id] &&
      this.flags[id] === other.flags[id]
    )
  }
}
