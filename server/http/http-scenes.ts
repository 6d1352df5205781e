/*
 * The saved scenes over HTTP (docs/scene-format.md): `POST /scenes` keeps a scene file (the body,
 * at most SCENE_LIMITS.bytes) and answers 201 with `{"id": ID}`, or 400 with the first error naming
 * the field, 413 for a body that is too large, 507 when the server keeps no more; `GET /scenes/ID`
 * sends a kept file (404 for an unknown id, 400 for a malformed one). A room opens a kept scene
 * with the `openScene` command, and a page opens one in a new room from a share link
 * (`/?scene=ID`). With a join token both routes need the join or admin key (`key=`), like /rooms.
 */
import type { IncomingMessage, ServerResponse } from 'node:http'
import { SCENE_LIMITS } from '../../games/index.ts'
import { SCENE_ID, type SceneStore } from '../scenes/index.ts'
import { SECURITY_HEADERS } from './http-headers.ts'

function reply(
  res: ServerResponse,
  status: number,
  type: string,
  body: string,
  extra: Record<string, string> = {},
): void {
  res.writeHead(status, { ...SECURITY_HEADERS, 'content-type': type, 'cache-control': 'no-store', ...extra })
  res.end(body)
}

/** Answer a request for /scenes or /scenes/ID. */
export function serveScenes(store: SceneStore, pathname: string, req: IncomingMessage, res: ServerResponse) {
  if (pathname === '/scenes') {
    if (req.method !== 'POST')
      return reply(res, 405, 'text/plain', 'POST a scene file to /scenes\n', { allow: 'POST' })
    return receiveScene(store, req, res)
  }
  if (req.method !== 'GET' && req.method !== 'HEAD')
    return reply(res, 405, 'text/plain', 'method not allowed\n')
  const id = pathname.slice('/scenes/'.length)
  if (!SCENE_ID.test(id)) return reply(res, 400, 'text/plain', 'a scene id is 16 hex digits\n')
  const stored = store.read(id)
  if (!stored.ok) return reply(res, 404, 'text/plain', `${stored.error}\n`)
  reply(res, 200, 'application/json', req.method === 'HEAD' ? '' : stored.text, {
    'content-disposition': `attachment; filename="scene-${id}.json"`,
  })
}

/** Read a POSTed scene (bounded), keep it, answer its id or the error. */
function receiveScene(store: SceneStore, req: IncomingMessage, res: ServerResponse) {
  const limit = SCENE_LIMITS.bytes
  const tooLarge = `a scene file is at most ${limit} bytes\n`
  const declared = Number(req.headers['content-length'] ?? 0)
  if (declared > limit) {
    reply(res, 413, 'text/plain', tooLarge, { connection: 'close' })
    req.destroy()
    return
  }
  const chunks: Buffer[] = []
  let size = 0
  let done = false
  req.on('data', (chunk: Buffer) => {
    if (done) return
    size += chunk.length
    if (size > limit) {
      done = true
      reply(res, 413, 'text/plain', tooLarge, { connection: 'close' })
      req.destroy()
      return
    }
    chunks.push(chunk)
  })
  req.on('error', () => {
    done = true
  })
  req.on('end', () => {
    if (done) return
    done = true
    let text: string
    try {
      text = new TextDecoder('utf-8', { fatal: true }).decode(Buffer.concat(chunks))
    } catch {
      return reply(res, 400, 'text/plain', 'a scene file must be UTF-8 text\n')
    }
    let stored: ReturnType<SceneStore['save']>
    try {
      stored = store.save(text)
    } catch (e) {
      return reply(res, 500, 'text/plain', `the scene could not be kept: ${(e as Error).message}\n`)
    }
    if (stored.ok) return reply(res, 201, 'application/json', JSON.stringify({ id: stored.id }))
    const full = stored.error.startsWith('this server')
    reply(res, full ? 507 : 400, 'text/plain', `${stored.error}\n`)
  })
}
