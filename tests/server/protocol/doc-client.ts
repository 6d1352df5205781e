/*
 * A client written from PROTOCOL.md alone, for the protocol tests: a plain `ws` socket, frames
 * encoded and decoded with @msgpack/msgpack (independent of the server's msgpackr codec), no
 * shared/ code. It keeps every decoded server message and the raw frames, and the close.
 */
import { decode, encode } from '@msgpack/msgpack'
import WebSocket from 'ws'
import { until } from '../../support/wait.ts'

/** A decoded server message: a map with a string `t`. */
export type Decoded = Record<string, unknown> & { t: string }

/** One socket speaking the documented protocol. */
export class DocClient {
  readonly messages: Decoded[] = []
  readonly frames: Uint8Array[] = []
  close: { code: number; reason: string } | null = null
  private constructor(readonly ws: WebSocket) {
    ws.on('message', (data: Buffer) => {
      this.frames.push(new Uint8Array(data))
      this.messages.push(decode(data) as Decoded)
    })
    ws.on('close', (code, reason) => {
      this.close = { code, reason: reason.toString() }
    })
    ws.on('error', () => {})
  }

  /** Open a socket to `base` (http://host:port) for `room`; resolves once open. */
  static async open(base: string, room: string): Promise<DocClient> {
    const ws = new WebSocket(`${base.replace('http', 'ws')}/ws?room=${room}`)
    const client = new DocClient(ws)
    await new Promise<void>((resolve, reject) => {
      ws.once('open', () => resolve())
      ws.once('error', reject)
    })
    return client
  }

  /** Open, join in snapshot mode and wait for the welcome. */
  static async joined(base: string, room: string, name: string): Promise<DocClient> {
    const client = await DocClient.open(base, room)
    client.send({ t: 'join', v: 3, room: '', name, mode: 'snapshot' })
    await client.waitFor((m) => m.t === 'welcome', 'welcome')
    return client
  }

  /** The welcome's player id. */
  get id(): number {
    return this.first('welcome').id as number
  }

  /** Encode a value with @msgpack/msgpack and send it as one binary frame. */
  send(value: unknown, options: { forceIntegerToFloat?: boolean } = {}): void {
    this.ws.send(encode(value, options))
  }

  /** Send raw bytes as one binary frame. */
  sendBytes(bytes: Uint8Array): void {
    this.ws.send(bytes)
  }

  /** The messages of one type received so far. */
  all(t: string): Decoded[] {
    return this.messages.filter((m) => m.t === t)
  }

  /** The first message of type `t` (throws when none came). */
  first(t: string): Decoded {
    const m = this.messages.find((x) => x.t === t)
    if (!m) throw new Error(`no ${t} message received`)
    return m
  }

  /** Wait until some received message passes `check`; returns it. */
  async waitFor(check: (m: Decoded) => boolean, what: string, timeoutMs = 15_000): Promise<Decoded> {
    await until(() => this.messages.some(check), what, timeoutMs)
    return this.messages.find(check)!
  }

  /** Wait until the server closes the socket; returns the close code and reason. */
  async closed(timeoutMs = 15_000): Promise<{ code: number; reason: string }> {
    await until(() => this.close !== null, 'the close', timeoutMs)
    return this.close!
  }

  /** Close from this side. */
  end(): void {
    this.ws.close()
  }
}

/** An independent reader of the snapshot `data` layout as PROTOCOL.md describes it. */
export function parseSnapshotData(
  bytes: Uint8Array,
): Array<{ id: number; flags: number; x: number; y: number; a: number }> {
  let i = 0
  const varint = (): number => {
    let value = 0
    let shift = 1
    for (;;) {
      const b = bytes[i++]
      if (b === undefined) throw new Error('truncated')
      value += (b & 127) * shift
      if (b < 128) return value
      shift *= 128
    }
  }
  const zigzag = (): number => {
    const u = varint()
    return u % 2 === 0 ? u / 2 : -(u + 1) / 2
  }
  const out = []
  let id = 0
  for (let n = varint(); n > 0; n--) {
    const head = varint()
    id += Math.floor(head / 4)
    out.push({ id, flags: head % 4, x: zigzag(), y: zigzag(), a: zigzag() })
  }
  if (i !== bytes.length) throw new Error('trailing bytes')
  return out
}
