/*
 * Plain HTTP on the same port as the WebSocket endpoint: the built browser client as static files,
 * health and readiness probes, Prometheus metrics, the open rooms as JSON for the lobby, and the
 * replay logs (GET /replays lists them, GET /replays/NAME downloads one), the browser bundle of each
 * game loaded with --games (GET /games/NAME.js, from memory), and for a plain GET /ws the
 * answer its upgrade would get (401/403 with the reason, else 200 saying whether the room controls
 * are allowed). Static paths are resolved
 * inside the static directory only (no traversal); a replay name must match the log name pattern
 * exactly, so it can only name a file directly inside the replay directory. With a join token the
 * room list and the replay routes need the join or admin key in the URL, as a join does
 * (http-access.ts checkKeyedRoute); 401 without one, 403 for a wrong one. With a metrics token,
 * /metrics needs it (`Authorization: Bearer TOKEN`, checkMetricsAccess). Every answer carries the
 * security headers of http-headers.ts. GET and HEAD only, but for POST /scenes (http-scenes.ts).
 * A request target that does not parse (`//%`) is answered 400 (http-request-url.ts).
 */
import { createReadStream } from 'node:fs'
import { stat } from 'node:fs/promises'
import type { IncomingMessage, ServerResponse } from 'node:http'
import { basename, extname, join, normalize, resolve, sep } from 'node:path'
import type { Logger } from 'pino'
import type { ServerMetrics } from '../hosting/index.ts'
import type { Recordings } from '../replay/index.ts'
import type { RoomHost } from '../rooms/index.ts'
import type { SceneStore } from '../scenes/index.ts'
import type { RoomSummary } from '../workers/index.ts'
import type { RouteRefusal } from './http-access.ts'
import { BENCH_PAGE, BENCH_SECURITY_HEADERS, SECURITY_HEADERS } from './http-headers.ts'
import { parseRequestTarget } from './http-request-url.ts'
import { serveScenes } from './http-scenes.ts'

const TYPES: Record<string, string> = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.json': 'application/json',
  '.map': 'application/json',
  '.svg': 'image/svg+xml',
  '.png': 'image/png',
  '.ico': 'image/x-icon',
  '.wasm': 'application/wasm',
  '.cclog': 'application/octet-stream',
}

/** What the routes need to answer. */
export interface RouteContext {
  staticDir: string
  /** The browser bundle of a game loaded with --games (GET /games/NAME.js), or undefined. */
  gameBundle?: (name: string) => string | undefined
  rooms: RoomHost
  recordings?: Recordings
  /** The saved scenes (POST /scenes, GET /scenes/ID); absent: those routes are 404. */
  scenes?: SceneStore
  /**
   * Null when a request for a keyed route (`/rooms`, `/replays`, `/replays/NAME`) may be
   * answered, else its refusal (checkKeyedRoute).
   */
  keyAccess: (url: URL, what: 'rooms' | 'replays' | 'scenes') => RouteRefusal | null
  /** Null when a request for /metrics may be answered, else its refusal (checkMetricsAccess). */
  metricsAccess: (req: IncomingMessage) => RouteRefusal | null
  /**
   * A plain GET /ws: the refusal its upgrade would get (status and a sentence), or, when it would
   * be let in (answered 200; a browser logs any other status as an error), whether its key opens the room controls. Browsers hide a failed
   * upgrade's status, so a page that cannot connect asks here whether its key is missing or wrong,
   * and a joined page whether its controls work (client/net/connection.ts).
   */
  wsAccess?: (req: IncomingMessage, url: URL) => { status: number; detail: string } | { controls: boolean }
  metrics: ServerMetrics
  /** The /metrics text when it is more than the registry's (room workers' metrics merged in). */
  metricsText?: () => Promise<string>
  log: Logger
  /**
   * Null when ready, else why not: shutting down (so load balancers stop sending players), or a
   * recording the operator requires (--require-recording) that cannot be written.
   */
  notReady: () => string | null
  /** Null while every tick loop runs; otherwise why /healthz fails (a stalled loop). */
  health: () => string | null
}

function send(
  res: ServerResponse,
  status: number,
  type: string,
  body: string,
  extra: Record<string, string> = {},
): void {
  res.writeHead(status, { ...SECURITY_HEADERS, 'content-type': type, 'cache-control': 'no-store', ...extra })
  res.end(body)
}

/** Answer a refused request for a keyed route. */
function refuse(res: ServerResponse, refusal: RouteRefusal): void {
  send(res, refusal.status, 'text/plain', `${refusal.text}\n`, refusal.headers)
}

/** The HTTP request handler. */
export function createRequestHandler(ctx: RouteContext): (req: IncomingMessage, res: ServerResponse) => void {
  const root = resolve(ctx.staticDir)
  const render = ctx.metricsText ?? (() => ctx.metrics.registry.metrics())
  // Requests for /metrics that arrive while it is being rendered share that rendering (it costs
  // about a millisecond of this thread, where the cheap routes cost a few microseconds).
  let rendering: Promise<string> | null = null
  const metricsText = (): Promise<string> => {
    rendering ??= render().finally(() => {
      rendering = null
    })
    return rendering
  }
  return (req, res) => {
    res.on('error', () => {})
    const url = parseRequestTarget(req.url)
    if (!url) return send(res, 400, 'text/plain', 'bad request target\n')
    if (ctx.scenes && (url.pathname === '/scenes' || url.pathname.startsWith('/scenes/'))) {
      const refusal = ctx.keyAccess(url, 'scenes')
      if (refusal) return refuse(res, refusal)
      return serveScenes(ctx.scenes, url.pathname, req, res)
    }
    if (req.method !== 'GET' && req.method !== 'HEAD')
      return send(res, 405, 'text/plain', 'method not allowed\n')
    switch (url.pathname) {
      case '/healthz': {
        const problem = ctx.health()
        return problem === null
          ? send(res, 200, 'text/plain', 'ok\n')
          : send(res, 503, 'text/plain', `${problem}\n`)
      }
      case '/readyz': {
        const problem = ctx.notReady()
        return problem === null
          ? send(res, 200, 'text/plain', 'ready\n')
          : send(res, 503, 'text/plain', `${problem}\n`)
      }
      case '/metrics': {
        const refusal = ctx.metricsAccess(req)
        if (refusal) return refuse(res, refusal)
        metricsText().then(
          (text) => send(res, 200, ctx.metrics.registry.contentType, text),
          () => send(res, 500, 'text/plain', 'metrics failed\n'),
        )
        return
      }
      case '/ws': {
        const access = ctx.wsAccess?.(req, url) ?? { controls: true }
        if ('detail' in access) return send(res, access.status, 'text/plain', `${access.detail}\n`)
        const controls = access.controls ? 'allowed' : 'need the admin key'
        return send(
          res,
          200,
          'text/plain',
          `WebSocket endpoint: upgrade to join (this key is accepted; room controls: ${controls})\n`,
        )
      }
      case '/rooms': {
        const refusal = ctx.keyAccess(url, 'rooms')
        if (refusal) return refuse(res, refusal)
        return send(res, 200, 'application/json', JSON.stringify(listRooms(ctx.rooms)))
      }
      case '/replays': {
        if (!ctx.recordings) return send(res, 404, 'text/plain', 'not found\n')
        const refusal = ctx.keyAccess(url, 'replays')
        if (refusal) return refuse(res, refusal)
        ctx.recordings.list().then(
          (logs) => send(res, 200, 'application/json', JSON.stringify(logs)),
          () => send(res, 500, 'text/plain', 'listing failed\n'),
        )
        return
      }
      default:
        if (url.pathname.startsWith('/games/') && ctx.gameBundle) {
          const name = /^\/games\/([a-z][a-z0-9-]{0,31})\.js$/.exec(url.pathname)?.[1]
          const code = name === undefined ? undefined : ctx.gameBundle(name)
          if (code !== undefined) return send(res, 200, TYPES['.js'], code, { 'cache-control': 'no-cache' })
        }
        if (url.pathname.startsWith('/replays/') && ctx.recordings) {
          const refusal = ctx.keyAccess(url, 'replays')
          if (refusal) return refuse(res, refusal)
          return serveReplay(ctx.recordings, url.pathname.slice('/replays/'.length), req, res, ctx.log)
        }
        serveStatic(root, url.pathname, req, res, ctx.log)
    }
  }
}

/** The open rooms for the lobby. */
export function listRooms(rooms: RoomHost): RoomSummary[] {
  return rooms.summaries()
}

/** Send one replay log; 400 for a name that is not a plain file name, 404 for any other non-log. */
function serveReplay(
  recordings: Recordings,
  encoded: string,
  req: IncomingMessage,
  res: ServerResponse,
  log: Logger,
): void {
  let name = ''
  try {
    name = decodeURIComponent(encoded)
  } catch {
    // Left empty: refused below.
  }
  if (name === '' || /[/\\\0]/.test(name) || name.includes('..')) {
    send(res, 400, 'text/plain', 'bad replay name\n')
    return
  }
  const dir = resolve(recordings.dir)
  const file = join(dir, name)
  if (!recordings.isLogName(name) || !file.startsWith(dir + sep)) {
    send(res, 404, 'text/plain', 'no such replay\n')
    return
  }
  serveFile(file, 'application/octet-stream', req, res, log, () =>
    send(res, 404, 'text/plain', 'no such replay\n'),
  )
}

function serveStatic(
  root: string,
  pathname: string,
  req: IncomingMessage,
  res: ServerResponse,
  log: Logger,
): void {
  let relative: string
  try {
    relative = decodeURIComponent(pathname)
  } catch {
    send(res, 400, 'text/plain', 'bad path\n')
    return
  }
  if (relative.includes('\0')) {
    send(res, 400, 'text/plain', 'bad path\n')
    return
  }
  if (relative.endsWith('/')) relative += 'index.html'
  const file = normalize(join(root, relative))
  if (file !== root && !file.startsWith(root + sep)) {
    send(res, 404, 'text/plain', 'not found\n')
    return
  }
  serveFile(file, TYPES[extname(file)] ?? 'application/octet-stream', req, res, log, () =>
    send(res, 404, 'text/plain', 'not found (is the client built? run npm start)\n'),
  )
}

/** Stream a regular file, or call `missing`. */
function serveFile(
  file: string,
  type: string,
  req: IncomingMessage,
  res: ServerResponse,
  log: Logger,
  missing: () => void,
): void {
  stat(file).then(
    (info) => {
      if (!info.isFile()) return missing()
      res.writeHead(200, {
        ...(basename(file) === BENCH_PAGE ? BENCH_SECURITY_HEADERS : SECURITY_HEADERS),
        'content-type': type,
        'content-length': info.size,
        'cache-control': 'no-cache',
      })
      if (req.method === 'HEAD' || info.size === 0) return res.end()
      // A log may grow while it is sent: send the size announced, no more.
      createReadStream(file, { end: info.size - 1 })
        .on('error', (error) => {
          log.warn({ err: error.message, file }, 'static file read failed')
          res.destroy()
        })
        .pipe(res)
    },
    () => missing(),
  )
}
