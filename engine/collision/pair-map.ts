/*
 * The contacts by body pair: an open-addressing hash table keyed by the two body ids (a < b).
 *
 * A JavaScript Map keyed by the pair key a * 2^26 + b allocates in the step: a key above 2^30 is
 * not a small integer, so every has/get/set/delete boxes it as a heap number, and a map with
 * contacts coming and going rehashes into a new table whenever its deleted entries pile up. Here
 * the ids sit in two Int32Arrays (linear probing, deletion by backward shift, so no tombstones);
 * only growth allocates. The table is never iterated, so its layout cannot affect results.
 */

/** Slots in a new table (a power of two). */
const INITIAL_CAPACITY = 64

/** Maps a pair of body ids (a < b, both in [0, 2^26)) to a value; allocation-free once grown. */
export class PairMap<T> {
  private idsA = new Int32Array(INITIAL_CAPACITY).fill(-1)
  private idsB = new Int32Array(INITIAL_CAPACITY)
  private values: (T | null)[] = emptyValues<T>(INITIAL_CAPACITY)
  private mask = INITIAL_CAPACITY - 1
  /** Number of pairs stored. */
  size = 0

  /** The value stored for pair (a, b), or undefined. */
  get(a: number, b: number): T | undefined {
    const i = this.find(a, b)
    return i < 0 ? undefined : (this.values[i] as T)
  }

  /** Whether pair (a, b) has a value. */
  has(a: number, b: number): boolean {
    return this.find(a, b) >= 0
  }

  /** Stores `value` for pair (a, b), replacing any value it had. */
  set(a: number, b: number, value: T): void {
    if (2 * (this.size + 1) > this.values.length) this.grow()
    const idsA = this.idsA
    const idsB = this.idsB
    let i = slotOf(a, b, this.mask)
    while (idsA[i] !== -1) {
      if (idsA[i] === a && idsB[i] === b) {
        this.values[i] = value
        return
      }
      i = (i + 1) & this.mask
    }
    idsA[i] = a
    idsB[i] = b
    this.values[i] = value
    this.size++
  }

  /** Removes pair (a, b); returns whether it was there. */
  delete(a: number, b: number): boolean {
    let i = this.find(a, b)
    if (i < 0) return false
    const idsA = this.idsA
    const idsB = this.idsB
    const values = this.values
    const mask = this.mask
    // Backward-shift deletion (Knuth 6.4, Algorithm R): move later entries of the probe run into
    // the hole when their home slot does not lie cyclically in (hole, entry].
    let j = i
    for (;;) {
      j = (j + 1) & mask
      if (idsA[j] === -1) break
      const home = slotOf(idsA[j], idsB[j], mask)
      if (i <= j ? i < home && home <= j : i < home || home <= j) continue
      idsA[i] = idsA[j]
      idsB[i] = idsB[j]
      values[i] = values[j]
      i = j
    }
    idsA[i] = -1
    values[i] = null
    this.size--
    return true
  }

  /** Removes every pair (keeping the table's size). */
  clear(): void {
    this.idsA.fill(-1)
    this.values.fill(null)
    this.size = 0
  }

  /** The slot holding pair (a, b), or -1. */
  private find(a: number, b: number): number {
    const idsA = this.idsA
    const idsB = this.idsB
    let i = slotOf(a, b, this.mask)
    for (;;) {
      const x = idsA[i]
      if (x === -1) return -1
      if (x === a && idsB[i] === b) return i
      i = (i + 1) & this.mask
    }
  }

  /** Doubles the table and re-inserts every pair. */
  private grow(): void {
    const oldA = this.idsA
    const oldB = this.idsB
    const oldValues = this.values
    const capacity = 2 * oldValues.length
    this.idsA = new Int32Array(capacity).fill(-1)
    this.idsB = new Int32Array(capacity)
    this.values = emptyValues<T>(capacity)
    this.mask = capacity - 1
    this.size = 0
    for (let i = 0; i < oldValues.length; i++) {
      if (oldA[i] !== -1) this.set(oldA[i], oldB[i], oldValues[i] as T)
    }
  }
}

/** A packed array of `n` nulls (a holey array would check for holes on every read). */
function emptyValues<T>(n: number): (T | null)[] {
  return Array.from({ length: n }, () => null)
}

/** Home slot of pair (a, b): a multiplicative hash of both ids (32-bit integer arithmetic). */
function slotOf(a: number, b: number, mask: number): number {
  const h = Math.imul(a, 0x9e3779b1) ^ Math.imul(b + 0x7f4a7c15, 0x85ebca6b)
  return (h ^ (h >>> 15)) & mask
}
