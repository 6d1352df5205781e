/*
 * One WebSocket to the server with automatic reconnect. It joins on open (with the reconnect
 * token of the previous welcome, so a dropped player keeps its identity and colour), decodes every
 * frame with the shared codec, and turns failures into messages a person can act on:
 * unreachable server, protocol version mismatch, full room, server shutting down, a missing or
 * wrong access key. It retries with exponential backoff (0.5 s doubling to 8 s) except after a
 * version mismatch or a refused key, where only a reload (a newer client, a fixed address) can help. A `moved` message (the room is held by another server) sends the
 * next connection to that server at once.
 */
import {
  CLOSE_CODES,
  type ClientMessage,
  decodeServerMessage,
  encodeMessage,
  type ServerMessage,
} from '../../shared/index.ts'

/** What the connection reports. */
export interface ConnectionHandlers {
  message(message: ServerMessage, bytes: number): void
  /** Status for the banner: null when joined and healthy. */
  /** `retryAtMs` (performance.now() time) is when the next attempt starts, for a countdown. */
  status(text: string | null, retrying: boolean, fatal: boolean, retryAtMs?: number): void
}

const MIN_BACKOFF_MS = 500
const MAX_BACKOFF_MS = 8000

/** A reconnecting WebSocket session. */
export class Connection {
  private ws: WebSocket | null = null
  private backoff = MIN_BACKOFF_MS
  private timer: ReturnType<typeof setTimeout> | null = null
  private lastError: { code: string; reason: string } | null = null
  private joined = false
  private closed = false
  /** Set by a `moved` message: the next connection goes to the room's server, at once. */
  private moved = false
  /** Bytes sent since creation. */
  bytesSent = 0

  constructor(
    private url: string,
    private readonly join: () => ClientMessage,
    private readonly handlers: ConnectionHandlers,
  ) {
    this.open()
  }

  /** True after a welcome on the current socket. */
  get isJoined(): boolean {
    return this.joined
  }

  private open(): void {
    this.joined = false
    this.lastError = null
    let ws: WebSocket
    try {
      ws = new WebSocket(this.url)
    } catch (error) {
      this.handlers.status(`Cannot open ${this.url}: ${(error as Error).message}`, false, true)
      return
    }
    ws.binaryType = 'arraybuffer'
    this.ws = ws
    ws.onopen = () => this.send(this.join())
    ws.onmessage = (event) => this.receive(event.data)
    ws.onclose = (event) => this.onClose(event.code, event.reason)
    ws.onerror = () => {}
  }

  private receive(data: unknown): void {
    if (!(data instanceof ArrayBuffer)) return
    const decoded = decodeServerMessage(new Uint8Array(data))
    if (!decoded.ok) {
      this.handlers.status(
        `The server sent something this client cannot read: ${decoded.reason}`,
        true,
        false,
      )
      return
    }
    const message = decoded.value
    if (message.t === 'welcome') {
      this.joined = true
      this.askControls()
      this.backoff = MIN_BACKOFF_MS
      this.handlers.status(null, false, false)
    }
    if (message.t === 'error') this.lastError = { code: message.code, reason: message.reason }
    if (message.t === 'moved') {
      const key = new URL(this.url).searchParams.get('key')
      const keyParam = key ? `&key=${encodeURIComponent(key)}` : ''
      this.url = `${message.url}/ws?room=${encodeURIComponent(message.room)}${keyParam}`
      this.moved = true
    }
    this.handlers.message(message, data.byteLength)
  }

  private onClose(code: number, reason: string): void {
    this.ws = null
    const wasJoined = this.joined
    this.joined = false
    if (this.closed) return
    if (this.moved) {
      // The room lives on another server (shared/protocol/PROTOCOL.md, `moved`): go there now.
      this.moved = false
      this.handlers.status(`Room moved to ${new URL(this.url).host}; connecting…`, true, false)
      this.open()
      return
    }
    const error = this.lastError
    if (code === CLOSE_CODES.version || error?.code === 'version') {
      const why = error?.reason ?? reason
      this.handlers.status(
        `Protocol mismatch: ${why}. Reload the page to get the current client.`,
        false,
        true,
      )
      return
    }
    if (!wasJoined && code === 1006) {
      // A refused upgrade looks like an unreachable server to a page: ask the server why first.
      this.probeAccess().then((refusal) => {
        if (this.closed || this.ws) return
        if (refusal) this.handlers.status(refusal, false, true)
        else this.retry(`Cannot reach the server at ${new URL(this.url).host}. Retrying`)
      })
      return
    }
    let text: string
    if (code === CLOSE_CODES.full || error?.code === 'full') {
      text = `Room full: ${error?.reason ?? reason}. Trying again`
      this.backoff = Math.max(this.backoff, 4000)
    } else if (code === CLOSE_CODES.goingAway)
      text = `The server is restarting (${reason || 'going away'}). Reconnecting`
    else text = `Connection lost${reason ? ` (${reason})` : ''}. Reconnecting`
    this.retry(text)
  }

  /** Show `text` with a countdown and open again after the backoff, which then doubles. */
  private retry(text: string): void {
    this.handlers.status(text, true, false, performance.now() + this.backoff)
    this.timer = setTimeout(() => {
      this.timer = null
      this.open()
    }, this.backoff)
    this.backoff = Math.min(MAX_BACKOFF_MS, this.backoff * 2)
  }

  /**
   * Why the server refuses this URL's upgrade, as a sentence for the banner, or null when it does
   * not (or cannot be asked). A plain GET of the WebSocket URL answers 401 (no key for a token-only
   * room) or 403 (a wrong key, or a page origin the server does not allow) with the reason; a
   * browser hides that status from a failed WebSocket, so without asking a refused page would
   * retry forever under "Cannot reach the server".
   */
  private async probeAccess(): Promise<string | null> {
    const answer = await this.askAccess()
    if (!answer || (answer.status !== 401 && answer.status !== 403)) return null
    const why = answer.text
    const hasKey = (new URL(this.url).searchParams.get('key') ?? '') !== ''
    if (answer.status === 401)
      return `Access key missing: ${why}. Add &key=KEY to the page address (ask whoever runs the server for the key) and reload.`
    if (hasKey && /key/.test(why))
      return `Access key wrong: ${why}. Fix &key= in the page address and reload.`
    return `The server refuses this page: ${why}.`
  }

  /** The answer to a plain GET of the WebSocket URL (status and text), or null when none came. */
  private async askAccess(): Promise<{ status: number; text: string } | null> {
    const probe = new URL(this.url)
    probe.protocol = probe.protocol === 'wss:' ? 'https:' : 'http:'
    try {
      const answer = await fetch(probe, { cache: 'no-store' })
      return { status: answer.status, text: (await answer.text()).trim() }
    } catch {
      return null
    }
  }

  /**
   * Whether this page's key opens the room controls (scene, reset, pause, step, gravity): false on
   * a server whose controls need the admin key when the page has not got it; null until known.
   * Asked once after the first welcome (a plain GET of the WebSocket URL answers 200 and says so).
   */
  controlsAllowed: boolean | null = null
  private controlsAsked = false

  private askControls(): void {
    if (this.controlsAsked) return
    this.controlsAsked = true
    void this.askAccess().then((answer) => {
      if (answer?.status === 200)
        this.controlsAllowed = !/room controls: need the admin key/.test(answer.text)
    })
  }

  /** Send a message if the socket is open; returns the bytes sent (0 when dropped). */
  send(message: ClientMessage): number {
    const ws = this.ws
    if (!ws || ws.readyState !== WebSocket.OPEN) return 0
    const bytes = encodeMessage(message)
    ws.send(bytes as Uint8Array<ArrayBuffer>)
    this.bytesSent += bytes.byteLength
    return bytes.byteLength
  }

  /** Reconnect now (e.g. a "retry" button), skipping the backoff wait. */
  retryNow(): void {
    if (this.ws || this.closed) return
    if (this.timer) clearTimeout(this.timer)
    this.timer = null
    this.open()
  }

  /** Close for good. */
  close(): void {
    this.closed = true
    if (this.timer) clearTimeout(this.timer)
    this.ws?.close(1000, 'leaving')
    this.ws = null
  }
}
