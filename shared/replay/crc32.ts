/*
 * CRC-32 (IEEE 802.3, as in zlib, PNG and gzip): reflected polynomial 0xEDB88320, initial value
 * and final XOR 0xFFFFFFFF; check value crc32("123456789") = 0xCBF43926. Table-driven, pure (runs
 * in browsers), used to checksum replay log records.
 */

const TABLE = (() => {
  const table = new Uint32Array(256)
  for (let n = 0; n < 256; n++) {
    let c = n
    for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1
    table[n] = c >>> 0
  }
  return table
})()

/** CRC-32 of bytes[start, end) as an unsigned 32-bit integer. */
export function crc32(bytes: Uint8Array, start = 0, end = bytes.length): number {
  let c = 0xffffffff
  for (let i = start; i < end; i++) c = TABLE[(c ^ bytes[i]) & 0xff] ^ (c >>> 8)
  return (c ^ 0xffffffff) >>> 0
}
