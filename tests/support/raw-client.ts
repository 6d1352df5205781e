/*
 * Raw TCP and WebSocket tools for attack tests: HTTP requests written byte for byte (so request
 * targets no HTTP library would send reach the server), hand-built masked WebSocket frames, a
 * reader of the server's frames (RFC 6455 5.2, written here independently of ws), a log capture
 * for a test server, and waiting on conditions by polling.
 */
import { connect, type Socket } from 'node:net'
import { Writable } from 'node:stream'
import pino, { type Logger } from 'pino'

/** The frame: {t: "ping", "é€…€": 1} with 31 euro signs, a 95-byte field name. */
export const LONG_NAME_FRAME = Buffer.from(`82a174a470696e67d95fc3a9${'e282ac'.repeat(31)}01`, 'hex')

/** Open a TCP connection to 127.0.0.1:port (from `localAddress`, another loopback address, if given). */
export function rawConnect(port: number, localAddress?: string): Promise<Socket> {
  return new Promise((resolve, reject) => {
    const socket = connect({ port, host: '127.0.0.1', localAddress }, () => resolve(socket))
    socket.once('error', reject)
  })
}

/** Everything the server sends on `socket` until it closes (resets count as a close). */
export function readUntilClosed(socket: Socket): Promise<Buffer> {
  const chunks: Buffer[] = []
  socket.on('data', (c: Buffer) => chunks.push(c))
  return new Promise((resolve) => {
    socket.on('error', () => {})
    socket.once('close', () => resolve(Buffer.concat(chunks)))
  })
}

/**
 * Write `text` on a fresh connection; resolves with the status code (0 if none) and the response
 * head once the head is complete (the socket is then closed), or with what came before a close.
 */
export async function rawRequest(
  port: number,
  text: string,
  localAddress?: string,
): Promise<{ status: number; answer: string }> {
  const socket = await rawConnect(port, localAddress)
  let received = ''
  const done = new Promise<void>((resolve) => {
    socket.on('data', (c: Buffer) => {
      received += c.toString('latin1')
      if (received.includes('\r\n\r\n')) resolve()
    })
    socket.on('error', () => {})
    socket.once('close', () => resolve())
  })
  socket.write(text)
  await done
  socket.destroy()
  const head = received.split('\r\n\r\n')[0]
  const status = /^HTTP\/1\.1 (\d{3})/.exec(head)
  return { status: status ? Number(status[1]) : 0, answer: head }
}

/** The request lines of a WebSocket upgrade for `target`, plus `extra` header lines. */
export function upgradeRequest(target: string, extra: string[] = []): string {
  return [
    `GET ${target} HTTP/1.1`,
    'Host: 127.0.0.1',
    'Upgrade: websocket',
    'Connection: Upgrade',
    'Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==',
    'Sec-WebSocket-Version: 13',
    ...extra,
    '',
    '',
  ].join('\r\n')
}

/** A frame read from the server. */
export interface ServerFrame {
  opcode: number
  payload: Buffer
}

/** A raw WebSocket: the socket after a 101, and the server frames parsed so far. */
export interface RawWebSocket {
  socket: Socket
  frames: ServerFrame[]
  closed: Promise<void>
}

/** Upgrade `target` on a raw socket; resolves after the 101 (rejects on any other status). */
export async function rawWebSocket(
  port: number,
  target: string,
  extra: string[] = [],
  localAddress?: string,
): Promise<RawWebSocket> {
  const socket = await rawConnect(port, localAddress)
  const frames: ServerFrame[] = []
  let buffer = Buffer.alloc(0)
  let upgraded = false
  const closed = new Promise<void>((resolve) => socket.once('close', () => resolve()))
  socket.on('error', () => {})
  return new Promise((resolve, reject) => {
    socket.on('data', (chunk: Buffer) => {
      buffer = Buffer.concat([buffer, chunk])
      if (!upgraded) {
        const end = buffer.indexOf('\r\n\r\n')
        if (end < 0) return
        const head = buffer.subarray(0, end).toString('latin1')
        buffer = buffer.subarray(end + 4)
        if (!head.startsWith('HTTP/1.1 101'))
          return reject(new Error(`upgrade refused: ${head.split('\r\n')[0]}`))
        upgraded = true
        resolve({ socket, frames, closed })
      }
      for (;;) {
        const frame = parseFrame(buffer)
        if (!frame) break
        frames.push(frame.frame)
        buffer = buffer.subarray(frame.length)
      }
    })
    socket.once('close', () => reject(new Error('closed before the upgrade')))
    socket.write(upgradeRequest(target, extra))
  })
}

/** One unmasked server frame at the start of `b`, or null if incomplete. */
function parseFrame(b: Buffer): { frame: ServerFrame; length: number } | null {
  if (b.length < 2) return null
  let length = b[1] & 0x7f
  let offset = 2
  if (length === 126) {
    if (b.length < 4) return null
    length = b.readUInt16BE(2)
    offset = 4
  } else if (length === 127) {
    if (b.length < 10) return null
    length = Number(b.readBigUInt64BE(2))
    offset = 10
  }
  if (b.length < offset + length) return null
  return {
    frame: { opcode: b[0] & 0x0f, payload: b.subarray(offset, offset + length) },
    length: offset + length,
  }
}

/** A final, masked client frame (opcode 2 = binary, 1 = text, 8 = close). */
export function clientFrame(payload: Uint8Array, opcode = 2): Buffer {
  const mask = Buffer.from([0x12, 0x34, 0x56, 0x78])
  const n = payload.length
  const head =
    n < 126
      ? Buffer.from([0x80 | opcode, 0x80 | n])
      : Buffer.from([0x80 | opcode, 0x80 | 126, n >> 8, n & 0xff])
  const body = Buffer.alloc(n)
  for (let i = 0; i < n; i++) body[i] = payload[i] ^ mask[i % 4]
  return Buffer.concat([head, mask, body])
}

/** A close frame's code and reason bytes. */
export function closeOf(frame: ServerFrame): { code: number; reason: Buffer } {
  return { code: frame.payload.readUInt16BE(0), reason: frame.payload.subarray(2) }
}

/** A logger that keeps every line it writes (JSON objects), for counting what a server logged. */
export function capturingLogger(level = 'info'): { logger: Logger; lines: Array<Record<string, unknown>> } {
  const lines: Array<Record<string, unknown>> = []
  const sink = new Writable({
    write(chunk: Buffer, _encoding, done) {
      for (const line of chunk.toString().split('\n')) if (line.trim()) lines.push(JSON.parse(line))
      done()
    },
  })
  return { logger: pino({ level }, sink), lines }
}

/** GET /healthz; true when it answers 200. */
export async function healthy(url: string): Promise<boolean> {
  try {
    return (await fetch(`${url}/healthz`)).status === 200
  } catch {
    return false
  }
}
