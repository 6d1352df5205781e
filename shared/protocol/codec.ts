/*
 * Framing: one MessagePack value per binary WebSocket frame. msgpackr is configured to write
 * standard MessagePack only (no records, no extensions), so any stock decoder reads the server.
 * Decoding never throws: it returns a result, and every client message must then pass the exact
 * schema check in validate.ts before anything uses it. msgpackr still decodes its extensions on
 * input whatever the options, so a client frame holding any extension type (or the never-used
 * header 0xc1) is refused before it is decoded (msgpack-extensions.ts), and the schema check keeps everything else exact.
 */
import { Packr, Unpackr } from 'msgpackr'
import type { ClientMessage, ServerMessage } from './messages.ts'
import { findNonStandard } from './msgpack-extensions.ts'
import { validateClientMessage, validateServerMessage } from './validate.ts'

const packr = new Packr({ useRecords: false, variableMapSize: true, encodeUndefinedAsNil: true })
const unpackr = new Unpackr({ useRecords: false, mapsAsObjects: true, int64AsType: 'number' })

/**
 * A decode outcome: the message, or a machine code and a human reason; a refused `input` whose own
 * `seq` is a valid sequence number carries it, so the error can echo it.
 */
export type DecodeResult<T> =
  | { ok: true; value: T }
  | { ok: false; code: string; reason: string; seq?: number }

/**
 * The `malformed` reason for a frame msgpackr could not decode, in the protocol's words: the
 * decoder's own message names its internals (and may echo the frame), so it is never quoted.
 */
function undecodableReason(error: unknown): string {
  const message = error instanceof Error ? error.message : ''
  if (message.includes('end of buffer not reached')) return 'bytes left over after the first value'
  if (/unexpected end/i.test(message)) return 'truncated: the frame ends inside a value'
  return 'not a standard MessagePack value'
}

/** Smallest whole number msgpackr writes as an integer (int 32); below it, it writes a float 64. */
const MIN_INT32 = -0x80000000
/** Largest whole number msgpackr writes as an integer (uint 32); above it, it writes a float 64. */
const MAX_UINT32 = 0xffffffff

/** True for a whole number that msgpackr would write as a float 64 (outside int 32 and uint 32). */
const isWideInteger = (n: number): boolean => Number.isInteger(n) && (n < MIN_INT32 || n > MAX_UINT32)

/**
 * True when `value` holds a number msgpackr would not write as the protocol says: a whole number
 * outside 32 bits (msgpackr writes a float 64 where PROTOCOL.md promises a MessagePack integer)
 * or, when `finite` is asked for, a NaN or an infinity. Typed arrays hold integers here.
 */
function needsRewrite(value: unknown, finite: boolean): boolean {
  if (typeof value === 'number') return isWideInteger(value) || (finite && !Number.isFinite(value))
  if (value === null || typeof value !== 'object' || ArrayBuffer.isView(value)) return false
  if (Array.isArray(value)) {
    // An index loop: for-of allocates an iterator, and every message sent passes through here.
    for (let i = 0; i < value.length; i++) if (needsRewrite(value[i], finite)) return true
    return false
  }
  for (const key in value) if (needsRewrite((value as Record<string, unknown>)[key], finite)) return true
  return false
}

/**
 * A copy of `value` as it must be packed: every whole number outside 32 bits up to 2^53 - 1 in
 * size as a BigInt, which msgpackr writes as a MessagePack int 64, and with `finite` every
 * non-finite number as 0. A whole float beyond 2^53 - 1 stays a float 64: no protocol integer is
 * that large, and it may not be the integer it looks like.
 */
function packable(value: unknown, finite: boolean): unknown {
  if (typeof value === 'number') {
    if (finite && !Number.isFinite(value)) return 0
    return Number.isSafeInteger(value) && isWideInteger(value) ? BigInt(value) : value
  }
  if (value === null || typeof value !== 'object' || ArrayBuffer.isView(value)) return value
  if (Array.isArray(value)) return value.map((v) => packable(v, finite))
  const out: Record<string, unknown> = {}
  for (const key in value) out[key] = packable((value as Record<string, unknown>)[key], finite)
  return out
}

/**
 * Encode a message as standard MessagePack bytes. Nothing non-finite is ever sent: a NaN or an
 * infinity (a world that went wrong) is written as 0, so a peer's decoder and schema check never
 * meet one; the world's sweep removes non-finite bodies within a second. Every whole number is a
 * MessagePack integer, the ones outside 32 bits (a ping id or a seq up to 2^53 - 1) an int 64.
 */
export function encodeMessage(message: ClientMessage | ServerMessage): Uint8Array {
  return packr.pack(needsRewrite(message, true) ? packable(message, true) : message)
}

/**
 * Encode any plain value (maps, arrays, strings, numbers, byte arrays) as standard MessagePack,
 * every whole number as an integer (as encodeMessage).
 */
export function encodeValue(value: unknown): Uint8Array {
  return packr.pack(needsRewrite(value, false) ? packable(value, false) : value)
}

/** Decode MessagePack bytes into an unvalidated value; never throws. */
export function decodeValue(bytes: Uint8Array): DecodeResult<unknown> {
  if (bytes.length === 0) return { ok: false, code: 'malformed', reason: 'empty frame' }
  try {
    return { ok: true, value: unpackr.unpack(bytes) }
  } catch (error) {
    return { ok: false, code: 'malformed', reason: `not MessagePack: ${undecodableReason(error)}` }
  }
}

/** Decode and validate a message from a client (standard MessagePack, no extensions); never throws. */
export function decodeClientMessage(bytes: Uint8Array): DecodeResult<ClientMessage> {
  const at = findNonStandard(bytes)
  if (at >= 0) {
    const header = bytes[at]
    const what =
      header === 0xc1 ? 'the never-used header 0xc1' : `an extension type (header 0x${header.toString(16)})`
    return { ok: false, code: 'malformed', reason: `not standard MessagePack: ${what} at byte ${at}` }
  }
  const decoded = decodeValue(bytes)
  if (!decoded.ok) return decoded
  return validateClientMessage(decoded.value)
}

/** Decode and shape-check a message from the server; never throws. */
export function decodeServerMessage(bytes: Uint8Array): DecodeResult<ServerMessage> {
  const decoded = decodeValue(bytes)
  if (!decoded.ok) return decoded
  return validateServerMessage(decoded.value)
}
