/*
 * A tower round between two client pages in headless Chromium (game-match-harness.ts: a real
 * server on 127.0.0.1 serving the client, the room watched on the server, recording on): one page
 * joined with `?game=tower&mode=lockstep` (lane 0) and one with `&mode=predict` (lane 1), each
 * building with a scripted block as soon as its cooldown allows (game-match-page.ts), sent over
 * its own connection as `cmd` messages, for the whole 60 s round. Then: at every tick a page was
 * seen at, its heights, fallen counts, phase and winners equal what the server's room held at that
 * tick (exactly: the heights are measured from the same world); the round ended with winners; no
 * desync in either page or on the server; the room's recorded log verifies.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { type TowerState, towerScore } from '../../games/index.ts'
import { until } from '../support/wait.ts'
import {
  closeMatchSetup,
  expectPageFollowed,
  expectServerClean,
  joinMatch,
  type MatchSetup,
  report,
  startMatchSetup,
  startScript,
  watchRoom,
} from './game-match-harness.ts'

const ROOM = 'tower-match'
let setup: MatchSetup

beforeAll(async () => {
  setup = await startMatchSetup('test-results/browser-tower-match/dist')
}, 180_000)

afterAll(async () => {
  await closeMatchSetup(setup)
})

describe('a tower round between a lockstep page and a predicting page', () => {
  it("both pages see the server's heights at every tick through the round, with no desync; the log replays", async () => {
    const lockstep = await joinMatch(setup, ROOM, 'tower', 'lockstep')
    const room = setup.server.rooms.get(ROOM)
    if (!room) throw new Error(`no room ${ROOM} on the server`)
    expect(room.game.name).toBe('tower')
    const summaries = watchRoom(room)
    const predict = await joinMatch(setup, ROOM, 'tower', 'predict')
    const state = () => room.sim.gameState as TowerState
    const players = [(await report(lockstep.page)).player, (await report(predict.page)).player]
    expect(players.map((p) => state().lanes[p])).toEqual([0, 1])

    // The state at the tick the round ended: the towers are measured on after it (blocks still
    // settle or fall), but the winners are decided from that tick's scores.
    let ended: TowerState | null = null
    room.sim.observers.push({
      command: () => {},
      join: () => {},
      leave: () => {},
      worldLoaded: () => {},
      ticked: () => {
        if (ended === null && state().phase === 'over') ended = structuredClone(state())
      },
    })
    await startScript(lockstep.page, 'builder')
    await startScript(predict.page, 'builder')
    await until(() => ended !== null, 'the end of the round on the server', 240_000)
    const serverTick = room.sim.tick
    const final = ended as unknown as TowerState
    const scores = players.map((p) => towerScore(final, p))
    console.log(
      `server at the end: heights ${JSON.stringify(final.height)}, fallen ${JSON.stringify(final.fallen)}, winners ${final.winners}; now tick ${serverTick}`,
    )
    // Both built all round (a block every 45 ticks or so; random kinds topple often: each fallen one counts).
    for (const p of players) {
      const placed = Object.values(final.blocks).filter((b) => b.owner === p).length + final.fallen[p]
      expect(placed).toBeGreaterThan(40)
    }
    const best = Math.max(...scores)
    expect(final.winners).toEqual(players.filter((_, i) => scores[i] === best))

    for (const [label, { page, errors }] of [
      ['lockstep', lockstep],
      ['predict', predict],
    ] as const) {
      const { seen, last } = await expectPageFollowed(label, page, summaries, serverTick)
      expect(seen.size).toBeGreaterThan(20)
      expect(JSON.parse(last.summary ?? 'null')[2]).toBe('over')
      expect(errors).toEqual([])
    }
    await expectServerClean(setup, ROOM, serverTick)
  }, 400_000)
})
