/*
 * The replay page (`?replay` opens the picker, `?replay=NAME` plays the server's log NAME): choose
 * a log from the server's list (GET /replays), a file picker or a file dropped on the page; then a
 * control bar under the canvas: play/pause, single step, speed, a seek bar, the tick, and the hash
 * check (green while every recorded checkpoint matched, red with the tick of the first mismatch).
 * A seek runs in slices (replay-player.ts), so a long one leaves the page live: the tick display
 * shows the tick reached, the target and the percent done; the seek bar shows the target; dragging
 * the bar again takes over; Play or Step pressed meanwhile act from where the seek lands.
 * With no server (a static page, a file: URL) the list is simply absent; files still play. The
 * page's `&key=` goes with every request for the server's logs (a server with a join token
 * refuses them without it, as it refuses a join).
 */
import { App } from '../app.ts'
import { findClientGame, loadGameModule } from '../modes/index.ts'
import { type LoadedLog, ReplayLoadError, readLog, type SeekProgress } from './replay-player.ts'
import { REPLAY_SPEEDS, ReplaySandbox } from './replay-sandbox.ts'

/** Inflate a zlib stream (RFC 1950) with the browser's DecompressionStream. */
export async function inflateZlib(bytes: Uint8Array): Promise<Uint8Array> {
  const stream = new Blob([bytes as Uint8Array<ArrayBuffer>])
    .stream()
    .pipeThrough(new DecompressionStream('deflate'))
  return new Uint8Array(await new Response(stream).arrayBuffer())
}

/** A log in the server's list (GET /replays, server/replay/replay-files.ts LogSummary). */
interface ListedLog {
  name: string
  room: string
  /** UTC ISO 8601. */
  start: string
  /** Seconds. */
  duration: number
  size: number
  status: 'clean' | 'recording' | 'torn' | 'corrupt' | 'empty' | 'invalid'
}

const el = <K extends keyof HTMLElementTagNameMap>(
  tag: K,
  props: Partial<HTMLElementTagNameMap[K]> = {},
  ...children: Array<Node | string>
): HTMLElementTagNameMap[K] => {
  const e = Object.assign(document.createElement(tag), props)
  e.append(...children)
  return e
}

/** How far a seek has come, in whole percent of the ticks it replays (0 until it has restored a keyframe). */
const progress = (seek: SeekProgress, tick: number): number =>
  seek.target > seek.from
    ? Math.min(100, Math.max(0, Math.floor((100 * (tick - seek.from)) / (seek.target - seek.from))))
    : 0

/** The replay page: picker, then the player with its controls. */
export class ReplayPage {
  sandbox: ReplaySandbox | null = null
  /** Logs asked to play so far; only the newest one's load goes on. */
  private loads = 0
  app: App | null = null
  readonly panel = el('div', { id: 'replay-panel', className: 'panel' })
  private readonly message = el('div', { id: 'replay-message' })

  constructor(
    private readonly httpBase: string,
    logName: string,
    /** The page's access key ('' for none), sent as `?key=` with every request for a log. */
    private readonly key = '',
  ) {
    document.body.append(this.panel)
    this.panel.style.cssText =
      'position:fixed;left:8px;right:8px;bottom:8px;display:flex;flex-wrap:wrap;gap:6px;align-items:center'
    document.getElementById('toolbar')?.setAttribute('hidden', '')
    this.acceptDrops()
    if (logName) {
      this.panel.replaceChildren(this.message)
      void this.fetchLog(logName)
    } else void this.showPicker()
  }

  /** The URL of a replay route (`/replays` or `/replays/NAME`), with the page's key. */
  private replayUrl(path: string): string {
    return `${this.httpBase}${path}${this.key ? `?key=${encodeURIComponent(this.key)}` : ''}`
  }

  private say(text: string, error = false): void {
    this.message.textContent = text
    this.message.style.color = error ? '#ff6b6b' : ''
  }

  private async showPicker(): Promise<void> {
    const file = el('input', {
      type: 'file',
      id: 'replay-file',
      accept: '.cclog,application/octet-stream',
    })
    file.addEventListener('change', () => {
      const f = file.files?.[0]
      if (f) void f.arrayBuffer().then((b) => this.play(new Uint8Array(b), f.name))
    })
    const list = el('div', { id: 'replay-list' })
    this.panel.replaceChildren(
      el('strong', {}, 'Replays'),
      this.message,
      el('label', {}, 'Open a file: ', file),
      el('span', {}, 'or drop one on the page'),
      list,
    )
    try {
      const res = await fetch(this.replayUrl('/replays'))
      if (res.status === 401 || res.status === 403) {
        list.textContent = `The server's logs need its key (HTTP ${res.status}): open this page with &key=KEY.`
        return
      }
      if (!res.ok) return
      const logs = (await res.json()) as ListedLog[]
      if (logs.length === 0) list.textContent = 'The server has no recorded sessions yet.'
      for (const log of logs) {
        if (log.status === 'invalid' || log.status === 'empty') continue
        const when = log.start.slice(0, 16).replace('T', ' ')
        const state = log.status === 'clean' ? '' : `, ${log.status}`
        const label = `${log.room} ${when} UTC, ${log.duration.toFixed(0)} s (${Math.round(log.size / 1024)} kB${state})`
        const b = el('button', { type: 'button' }, label)
        b.dataset.log = log.name
        b.addEventListener('click', () => void this.fetchLog(log.name))
        list.append(b)
      }
    } catch {
      // No server (a static page): files still play.
    }
  }

  private acceptDrops(): void {
    window.addEventListener('dragover', (e) => e.preventDefault())
    window.addEventListener('drop', (e) => {
      e.preventDefault()
      const f = e.dataTransfer?.files[0]
      if (f) void f.arrayBuffer().then((b) => this.play(new Uint8Array(b), f.name))
    })
  }

  /**
   * Fetch the server's log `name` and play it; when that fails, the reason stays on the page above
   * the picker (the server's list, a file, a drop), never a blank page.
   */
  private async fetchLog(name: string): Promise<void> {
    this.say(`loading ${name}...`)
    const problem = await this.fetchProblem(name)
    if (problem === null) return
    this.say(problem, true)
    await this.showPicker()
  }

  /** Null once the log plays (or a newer load took over), else why it cannot be opened. */
  private async fetchProblem(name: string): Promise<string | null> {
    const shown = name.length > 60 ? `${name.slice(0, 60)}…` : name
    const looksLikeLog = /\.cclog$/.test(name) && !/[/\\]/.test(name)
    const hint = looksLikeLog
      ? ''
      : ` A replay is named by its log file (ROOM-DATE.cclog, as in the list), not by a room name or a path.`
    let res: Response
    try {
      res = await fetch(this.replayUrl(`/replays/${encodeURIComponent(name)}`))
    } catch (error) {
      return `Cannot fetch the log "${shown}": ${(error as Error).message}. Open a log file instead.`
    }
    if (res.status === 401 || res.status === 403)
      return `The server's log "${shown}" needs its key (HTTP ${res.status}): open this page with &key=KEY.`
    if (!res.ok) {
      const said = (await res.text().catch(() => '')).trim()
      return `Cannot open the replay "${shown}": ${said || 'the server has no such log'} (HTTP ${res.status}).${hint}`
    }
    await this.play(new Uint8Array(await res.arrayBuffer()), name)
    return null
  }

  /** Load bytes as a log and start the player; a bad file gets one line saying what is wrong. */
  async play(bytes: Uint8Array, name: string): Promise<void> {
    // Reading a big log takes slices of main thread; a file opened meanwhile takes over.
    const load = ++this.loads
    let log: LoadedLog
    try {
      log = await readLog(bytes, (done) => this.say(`reading ${name}: ${Math.floor(100 * done)} %`))
    } catch (error) {
      if (!(error instanceof ReplayLoadError)) throw error
      if (load !== this.loads) return
      this.panel.append(this.message)
      this.say(`${name}: ${error.message}`, true)
      return
    }
    if (load !== this.loads) return
    // A game this build does not ship: the page's server serves it (--games DIR) at /games/NAME.js.
    let sandbox: ReplaySandbox
    try {
      const game = log.header.state.game
      if (!findClientGame(game)) {
        if (!this.httpBase)
          throw new Error(`the log was recorded with game "${game}", which this page does not have`)
        await loadGameModule(this.httpBase.replace(/^http/, 'ws'), game)
      }
      sandbox = await ReplaySandbox.open(log, inflateZlib)
    } catch (error) {
      if (load !== this.loads) return
      this.panel.append(this.message)
      this.say(`${name}: ${(error as Error).message}`, true)
      return
    }
    if (load !== this.loads) return
    this.sandbox?.dispose()
    this.sandbox = sandbox
    this.app?.stop()
    this.app = new App(sandbox, this.httpBase, log.header.room)
    window.concord = this.app
    this.controls(log, name)
    // Framed once the control bar is in: the scene sits above it, the HUD too (placePanels).
    this.app.placePanels()
    this.app.fit()
  }

  private controls(log: LoadedLog, name: string): void {
    const s = this.sandbox!
    const play = el('button', { type: 'button', id: 'replay-play' }, 'Play')
    const step = el('button', { type: 'button', id: 'replay-step' }, 'Step')
    const speed = el('select', { id: 'replay-speed', title: 'Speed' })
    for (const v of REPLAY_SPEEDS)
      speed.append(el('option', { value: String(v), selected: v === 1 }, `${v}x`))
    const seek = el('input', {
      type: 'range',
      id: 'replay-seek',
      min: String(log.firstTick),
      max: String(log.lastTick),
    })
    seek.style.flex = '1'
    const tick = el('span', { id: 'replay-tick' })
    const hash = el('span', { id: 'replay-hash' })
    const kept =
      log.status.state === 'end'
        ? ''
        : ` (${log.status.state}: kept ${log.status.records} records to tick ${log.lastTick}; ${log.status.reason})`
    play.addEventListener('click', () => {
      if (s.player.atEnd && !s.player.busy)
        void s.seek(log.firstTick).then((arrived) => (s.playing = arrived))
      else s.playing = !s.playing
    })
    step.addEventListener('click', () => void s.stepOnce())
    speed.addEventListener('change', () => (s.speed = Number(speed.value)))
    seek.addEventListener('input', () => void s.seek(Number(seek.value)))
    this.panel.replaceChildren(
      el('strong', {}, `${log.header.room}`),
      play,
      step,
      speed,
      seek,
      tick,
      hash,
      el('a', { href: '?replay' }, 'Other logs'),
      this.message,
    )
    this.say(`${name}${kept}`, kept !== '')
    const refresh = (): void => {
      play.textContent = s.playing ? 'Pause' : 'Play'
      const t = s.player.tick
      const seeking = s.player.seeking
      if (document.activeElement !== seek) seek.value = String(seeking?.target ?? t)
      const secs = (t - log.firstTick) / 60
      tick.textContent = seeking
        ? `tick ${t} / ${log.lastTick}  seeking to ${seeking.target}: ${progress(seeking, t)} %`
        : `tick ${t} / ${log.lastTick}  ${secs.toFixed(1)} s`
      tick.dataset.seeking = seeking ? 'true' : 'false'
      const bad = s.player.mismatch
      hash.textContent = bad
        ? `hash mismatch at tick ${bad.tick}`
        : `hashes match (${s.player.checked} checked)`
      hash.dataset.ok = bad ? 'false' : 'true'
      hash.style.color = bad ? '#ff6b6b' : '#5cd67a'
      if (this.sandbox === s) requestAnimationFrame(refresh)
    }
    refresh()
  }
}
