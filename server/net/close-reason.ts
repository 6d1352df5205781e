/*
 * A WebSocket close frame carries at most 123 bytes of UTF-8 reason (RFC 6455 5.5: 125 bytes of
 * payload, 2 of them the code), and ws throws a RangeError for a longer one. Reasons often quote
 * what a client sent, so they are cut here on a character boundary: cutting a multi-byte
 * character in half made ws throw inside a message handler and ended the process (issue 11).
 */

/** Most bytes of reason a close frame can carry. */
export const MAX_CLOSE_REASON_BYTES = 123

/** `text` cut to at most `maxBytes` bytes of UTF-8 without splitting a character. */
export function cutUtf8(text: string, maxBytes: number = MAX_CLOSE_REASON_BYTES): string {
  const bytes = Buffer.from(text, 'utf8')
  if (bytes.length <= maxBytes) return text
  let end = maxBytes
  // Step back over continuation bytes (10xxxxxx) to the first byte of the cut character.
  while (end > 0 && (bytes[end] & 0xc0) === 0x80) end--
  return bytes.subarray(0, end).toString('utf8')
}
