/*
 * Entry point. The URL decides the mode:
 *   ?room=NAME      join that room on the server that served this page (a link invites a friend)
 *   ?offline        run the engine in the page, no server (&scene=NAME picks the scene); the
 *                   static build (npm run build:static) always runs offline
 *   ?scene=ID       open a saved scene (a share link) in a new room of its own
 *   ?replay[=NAME]  play a recorded log: the server's log NAME, or pick one (list, file, drop)
 *   &key=KEY        access key of a server with join or admin tokens (sent on to the WebSocket,
 *                   and to GET /replays, which a server with a join token refuses without it)
 *   &name=NAME      player name (default: the name last chosen in this browser's player list, else
 *                   "guest" and a number)
 *   &server=URL     a WebSocket URL other than this page's origin (ws://host:port/ws)
 *   &game=GAME      the game a new room runs (docs/games.md; fixed when the room is created)
 *   &mode=lockstep  simulate the room in the page from the server's tick stream (&mode=predict:
 *                   also apply this player's own inputs at once, with rollback)
 * Without ?room the page joins the server's default room and writes it into the address bar.
 */
import { DEFAULT_SCENE } from '../engine/index.ts'
import { App, hasServer } from './app.ts'
import { LockstepSandbox, OfflineSandbox, OnlineSandbox, type Sandbox } from './modes/index.ts'
import { NAME_KEY } from './player-list.ts'
import { ReplayPage } from './replay/index.ts'

function boot(): App {
  const params = new URLSearchParams(location.search)
  const httpBase = `${location.protocol}//${location.host}`
  // A share link (?scene=ID, no room) opens the saved scene in a new room of its own.
  const shared =
    /^[0-9a-f]{16}$/.test(params.get('scene') ?? '') && !params.has('offline') ? params.get('scene') : null
  if (shared && !params.has('room')) {
    params.set('room', `s-${shared.slice(0, 8)}-${Math.floor(Math.random() * 9000 + 1000)}`)
    // A reload stays in that room and does not open the scene again.
    params.delete('scene')
    history.replaceState(null, '', `?${params.toString()}`)
  }
  const room = params.get('room') || 'lobby'
  let sandbox: Sandbox
  // The static build (npm run build:static) marks its page: a static host has no game server.
  if (params.has('offline') || !hasServer()) {
    sandbox = new OfflineSandbox(params.get('scene') ?? DEFAULT_SCENE)
  } else {
    if (!params.has('room')) {
      params.set('room', room)
      history.replaceState(null, '', `?${params.toString()}`)
    }
    const ws =
      params.get('server') || `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws`
    const name = params.get('name') || savedName() || `guest ${Math.floor(Math.random() * 900 + 100)}`
    const mode = params.get('mode')
    const key = params.get('key') ?? undefined
    const game = params.get('game') ?? undefined
    sandbox =
      mode === 'lockstep' || mode === 'predict'
        ? new LockstepSandbox({ url: ws, room, name, mode, key, game })
        : new OnlineSandbox({ url: ws, room, name, key, game })
  }
  return new App(sandbox, httpBase, room, shared)
}

declare global {
  interface Window {
    /** The running page, for the browser tests and for poking at the sandbox from the console. */
    concord: App
    /** The replay page, in replay mode (`?replay`). */
    concordReplay?: ReplayPage
  }
}

const pageParams = new URLSearchParams(location.search)
const replay = pageParams.get('replay')
if (replay !== null) {
  const base = location.protocol === 'file:' ? '' : `${location.protocol}//${location.host}`
  window.concordReplay = new ReplayPage(base, replay, pageParams.get('key') ?? '')
} else {
  window.concord = boot()
}

/** The name this browser's player last chose in the player list (player-list.ts), or ''. */
function savedName(): string {
  try {
    return localStorage.getItem(NAME_KEY) ?? ''
  } catch {
    return ''
  }
}
