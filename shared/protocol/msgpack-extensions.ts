/*
 * Finding MessagePack extension types (and the never-used header 0xc1) in a client's frame before
 * decoding it. The protocol allows none, but msgpackr decodes its own extensions whatever the
 * options (timestamps to Dates, type 0 to `undefined`, records, sets, typed arrays) and reads 0xc1
 * as a value, and `undefined` would pass for an absent optional field. Walking the frame's
 * structure once (frames are at most a few KiB) lets all of them be refused the same way, as
 * `malformed`, whatever msgpackr would make of them.
 *
 * The walk follows the MessagePack spec's type table (github.com/msgpack/msgpack, spec.md): it
 * skips each value by its header, counting the values still owed by open arrays and maps.
 */

/** Bytes taken by a header byte's own fields (after the type byte) for fixed-size types. */
const FIXED: Readonly<Record<number, number>> = {
  192: 0, // nil
  194: 0, // false
  195: 0, // true
  202: 4, // float 32
  203: 8, // float 64
  204: 1, // uint 8
  205: 2, // uint 16
  206: 4, // uint 32
  207: 8, // uint 64
  208: 1, // int 8
  209: 2, // int 16
  210: 4, // int 32
  211: 8, // int 64
}

/** Extension headers: fixext 1/2/4/8/16 and ext 8/16/32. */
const EXTENSIONS = new Set([0xc7, 0xc8, 0xc9, 0xd4, 0xd5, 0xd6, 0xd7, 0xd8])

/**
 * Offset of the first header in `bytes` that standard MessagePack without extensions does not
 * allow (an extension type, or 0xc1, which the spec never uses), or -1 when there is none before
 * the first value ends (or the bytes end first: the decoder then reports the truncation).
 */
export function findNonStandard(bytes: Uint8Array): number {
  const n = bytes.length
  const big = (at: number, size: number): number => {
    let v = 0
    for (let k = 0; k < size; k++) v = v * 256 + (bytes[at + k] ?? 0)
    return v
  }
  let i = 0
  let owed = 1
  while (owed > 0 && i < n) {
    owed--
    const b = bytes[i]
    if (b <= 0x7f || b >= 0xe0)
      i += 1 // positive or negative fixint
    else if (b <= 0x8f) {
      owed += 2 * (b & 0x0f) // fixmap
      i += 1
    } else if (b <= 0x9f) {
      owed += b & 0x0f // fixarray
      i += 1
    } else if (b <= 0xbf)
      i += 1 + (b & 0x1f) // fixstr
    else if (EXTENSIONS.has(b)) return i
    else if (Object.hasOwn(FIXED, b)) i += 1 + FIXED[b]
    else if (b === 0xc4 || b === 0xd9)
      i += 2 + big(i + 1, 1) // bin 8, str 8
    else if (b === 0xc5 || b === 0xda)
      i += 3 + big(i + 1, 2) // bin 16, str 16
    else if (b === 0xc6 || b === 0xdb)
      i += 5 + big(i + 1, 4) // bin 32, str 32
    else if (b === 0xdc || b === 0xdd) {
      const size = b === 0xdc ? 2 : 4 // array 16, array 32
      owed += big(i + 1, size)
      i += 1 + size
    } else if (b === 0xde || b === 0xdf) {
      const size = b === 0xde ? 2 : 4 // map 16, map 32
      owed += 2 * big(i + 1, size)
      i += 1 + size
    } else return i // 0xc1: never used
  }
  return -1
}
