// The SDK example page (docs/sdk.md): uses nothing but the built SDK, served beside it as /sdk/.
// ?room=NAME picks the room (default sdk-demo), &game=GAME the game of a room it opens, &mode=
// snapshot|lockstep|predict how it follows the room. It shows the body count and the players,
// spawns a box with a built-in command and, in a room with a `kick` command (the goal game), sends
// that custom command; the world is drawn with the SDK's renderer.
import { connect } from '/sdk/index.js'
import { createRenderer } from '/sdk/render.js'

const params = new URLSearchParams(location.search)
const $ = (id) => document.getElementById(id)

try {
  const session = await connect({
    url: location.origin,
    room: params.get('room') ?? 'sdk-demo',
    name: params.get('name') ?? 'sdk-page',
    mode: params.get('mode') ?? 'snapshot',
    ...(params.get('game') ? { game: params.get('game') } : {}),
  })
  window.sdkSession = session
  $('status').textContent = `joined ${session.room} (${session.rules.game}) as #${session.id}`
  createRenderer($('world'), session)
  const show = () => {
    $('bodies').textContent = String(session.bodies().length)
    $('players').textContent = session
      .players()
      .map((p) => p.name)
      .join(', ')
  }
  show()
  session.on('state', show)
  session.on('error', (e) => {
    $('last').textContent = `refused (${e.code}): ${e.reason}`
  })
  session.on('event', ({ tick, event }) => {
    $('last').textContent = `tick ${tick}: ${JSON.stringify(event)}`
  })
  session.on('close', ({ code, reason }) => {
    $('status').textContent = `closed (${code} ${reason})`
  })
  $('spawn').disabled = false
  $('spawn').onclick = () => {
    const x = Math.round((Math.random() * 8 - 4) * 10) / 10
    session.send({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x, y: 10, color: 0xf0a030 })
  }
  if (session.rules.commands.includes('kick')) {
    $('kick').hidden = false
    $('kick').onclick = () => session.command('kick', { power: 1 })
  }
} catch (error) {
  $('status').textContent = error.message
}
