/*
 * Framing: one MessagePack value per binary WebSocket frame. msgpackr is configured to write
 * standard MessagePack only (no records, no extensions), so any stock decoder reads the server.
 * Decoding never throws: it returns a result, and every client message must then pass the exact
 * schema check in validate.ts before anything uses it (msgpackr still decodes its extensions on
 * input whatever the options, so the schema check is what keeps Dates, BigInts and typed arrays
 * out of the rooms).
 */
import { Packr, Unpackr } from 'msgpackr'
import type { ClientMessage, ServerMessage } from './messages.ts'
import { validateClientMessage, validateServerMessage } from './validate.ts'

const packr = new Packr({ useRecords: false, variableMapSize: true, encodeUndefinedAsNil: true })
const unpackr = new Unpackr({ useRecords: false, mapsAsObjects: true, int64AsType: 'number' })

/** A decode outcome: the message, or a machine code and a human reason. */
export type DecodeResult<T> = { ok: true; value: T } | { ok: false; code: string; reason: string }

/** Encode a message as standard MessagePack bytes. */
export function encodeMessage(message: ClientMessage | ServerMessage): Uint8Array {
  return packr.pack(message)
}

/** Decode MessagePack bytes into an unvalidated value; never throws. */
export function decodeValue(bytes: Uint8Array): DecodeResult<unknown> {
  if (bytes.length === 0) return { ok: false, code: 'malformed', reason: 'empty frame' }
  try {
    return { ok: true, value: unpackr.unpack(bytes) }
  } catch (error) {
    return { ok: false, code: 'malformed', reason: `not MessagePack: ${(error as Error).message}` }
  }
}

/** Decode and validate a message from a client; never throws. */
export function decodeClientMessage(bytes: Uint8Array): DecodeResult<ClientMessage> {
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
