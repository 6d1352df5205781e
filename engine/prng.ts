/*
 * Seeded integer PRNG for scenes and tests: mulberry32 (Tommy Ettinger), built from Math.imul and
 * 32-bit integer operations only, so every JavaScript engine yields the same sequence.
 */

/** A deterministic random source; `next()` returns a float in [0, 1) with 32 random bits. */
export class Prng {
  private state: number

  constructor(seed: number) {
    this.state = seed >>> 0
  }

  /** The generator's position (32-bit unsigned): `new Prng(p.position())` continues p's sequence. */
  position(): number {
    return this.state
  }

  /** Next 32-bit unsigned integer. */
  nextUint32(): number {
    this.state = (this.state + 0x6d2b79f5) >>> 0
    let t = this.state
    t = Math.imul(t ^ (t >>> 15), t | 1)
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61)
    return (t ^ (t >>> 14)) >>> 0
  }

  /** Next float in [0, 1). */
  next(): number {
    return this.nextUint32() / 4294967296
  }

  /** Next float in [lo, hi). */
  range(lo: number, hi: number): number {
    return lo + (hi - lo) * this.next()
  }

  /** Next integer in [0, n). */
  int(n: number): number {
    return Math.floor(this.next() * n)
  }
}
