/*
 * A goal match between two client pages in headless Chromium (game-match-harness.ts: a real
 * server on 127.0.0.1 serving the client, rooms on the main thread so the test watches the room's
 * own simulation, recording on): one page joined with `?game=goal&mode=lockstep` (red, the first
 * to join) and one with `&mode=predict` (blue). Each page plays its player with a script
 * (game-match-page.ts: the red page a striker, the blue page keeps out of the way) computed from
 * its own simulation and sent over its own connection as `cmd` messages, until the match ends:
 * red wins, 5-0 when the pages keep up, or ahead when the two-minute match clock runs out first
 * (the scripts act in real time while the match clock counts ticks, so a loaded machine scores
 * fewer goals: a full CI run once ended 2-0 on the clock). Then: at every tick a page was seen at (every 5 ms through the match), its score
 * and phase equal what the server's room held at that tick; neither page reported a desync (each
 * page's count is 0 after at least two checkpoints, the server's concord_desyncs_total is 0); and
 * the room's recorded log verifies with `npm run replay -- FILE --verify`.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { type GoalState, MATCH_TICKS, WIN_SCORE } from '../../games/index.ts'
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

const ROOM = 'goal-match'
let setup: MatchSetup

beforeAll(async () => {
  setup = await startMatchSetup('test-results/browser-game-match/dist')
}, 180_000)

afterAll(async () => {
  await closeMatchSetup(setup)
})

describe('a goal match between a lockstep page and a predicting page', () => {
  it(`red wins (${WIN_SCORE}-0, or ahead on the clock); both pages see the server's score at every tick they simulate, with no desync; the log replays`, async () => {
    const lockstep = await joinMatch(setup, ROOM, 'goal', 'lockstep')
    const room = setup.server.rooms.get(ROOM)
    if (!room) throw new Error(`no room ${ROOM} on the server`)
    expect(room.game.name).toBe('goal')
    const summaries = watchRoom(room)
    const predict = await joinMatch(setup, ROOM, 'goal', 'predict')
    const state = () => room.sim.gameState as GoalState
    expect(state().players[(await report(lockstep.page)).player].team).toBe('red')
    expect(state().players[(await report(predict.page)).player].team).toBe('blue')

    await startScript(lockstep.page, 'striker')
    await startScript(predict.page, 'bench')
    await until(() => state().phase === 'over', 'the end of the match on the server', 240_000)
    const { score, winner, startTick } = state()
    const serverTick = room.sim.tick
    console.log(`server: ${JSON.stringify(score)} at tick ${serverTick}`)
    expect(winner).toBe('red')
    expect(score.blue).toBe(0)
    expect(score.red).toBeGreaterThanOrEqual(1)
    // Short of five goals, the match ended on its clock.
    if (score.red < WIN_SCORE) expect(serverTick - startTick).toBeGreaterThanOrEqual(MATCH_TICKS)

    const end = JSON.stringify([score, 'over'])
    for (const [label, { page, errors }] of [
      ['lockstep', lockstep],
      ['predict', predict],
    ] as const) {
      const { seen, last } = await expectPageFollowed(label, page, summaries, serverTick)
      // The page saw the match go 0-0, 1-0, ... to the final score and end.
      expect(seen.size).toBeGreaterThanOrEqual(score.red + 1)
      expect(seen).toContain(end)
      expect(last.summary).toBe(end)
      expect(errors).toEqual([])
    }
    await expectServerClean(setup, ROOM, serverTick)
  }, 400_000)
})
