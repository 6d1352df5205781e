/*
 * A predicting client predicts its own game commands (issue 29: "a predicting client rolls back
 * and converges"), over real sockets: a goal room on a real server, red a PredictClient (stepped
 * by the test, frame by frame, as a page steps from requestAnimationFrame), blue a snapshot
 * player. Red's `run` and `kick` (goal-game commands, `cmd` on the wire) show in red's present
 * (the game state's target velocity, the kick's tick and the ball's velocity) as soon as they are
 * sent, while the confirmed simulation, which only the server's stream moves, does not have them
 * yet; the stream then confirms them. The oracles: the server's hash checkpoints (the confirmed
 * simulation checks every one, no desync), and the confirmed simulation's hash at every tick
 * against the present's hash at the same tick once no own command is pending.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { LockstepBot } from '../../../bots/lockstep-bot.ts'
import { BALL_RADIUS, type GoalState, KICK_REACH, PLAYER_RADIUS } from '../../../games/index.ts'
import type { RunningServer } from '../../../server/server.ts'
import type { PredictClient, RoomSimulation } from '../../../shared/index.ts'
import { startTestServer } from '../../support/test-server.ts'

let server: RunningServer
beforeAll(async () => {
  server = await startTestServer()
})
afterAll(async () => {
  await server?.close()
})

const goalState = (sim: RoomSimulation | null): GoalState => sim?.gameState as GoalState

describe('predict mode and game commands', { timeout: 120_000 }, () => {
  it("applies the player's own run and kick at once, and converges to the server's state", async () => {
    // The test steps the runner itself (the bot's own frame timer never fires in the test's time).
    const red = await LockstepBot.connect(
      { url: server.url, room: 'pg', name: 'red', game: 'goal' },
      'predict',
      1e9,
    )
    const runner = red.runner as PredictClient
    const blue = await BotClient.connect({ url: server.url, room: 'pg', name: 'blue', game: 'goal' })
    const me = runner.playerId

    // Every confirmed tick's hash, from an observer on the confirmed simulation.
    const confirmed = new Map<number, number>()
    let observed: RoomSimulation | null = null
    const frame = (): void => {
      runner.advance(performance.now())
      const sim = runner.sim
      if (sim && sim !== observed) {
        observed = sim
        sim.observers.push({
          command: () => {},
          join: () => {},
          leave: () => {},
          worldLoaded: () => {},
          ticked: (tick) => confirmed.set(tick, sim.hash()),
        })
      }
    }
    /** Step frames (16 ms apart) until `condition` holds. */
    const frames = async (condition: () => boolean, what: string, limit = 60_000): Promise<void> => {
      const start = performance.now()
      for (;;) {
        frame()
        if (condition()) return
        if (performance.now() - start > limit) throw new Error(`timed out waiting for ${what}`)
        await new Promise((r) => setTimeout(r, 16))
      }
    }
    await frames(() => goalState(runner.present)?.phase === 'playing', 'kickoff in the present')
    expect(goalState(runner.present).players[me]).toMatchObject({ team: 'red', vx: 0, vy: 0 })

    // run: the present has it at once; the confirmed simulation gets it from the stream.
    runner.gameCommand('run', { x: 1, y: 0 }, performance.now())
    expect(goalState(runner.present).players[me]).toMatchObject({ vx: 1, vy: 0 })
    expect(goalState(runner.sim).players[me]).toMatchObject({ vx: 0, vy: 0 })
    await frames(() => goalState(runner.sim).players[me].vx === 1, 'the run confirmed')

    // kick: sent when the present has the ball in reach (red walks it along at 1 m/s); the present
    // shows the kick's tick and the ball's new speed at once. The server may still refuse a kick
    // predicted a tick off (the ball just out of reach): then the present rolls back and red tries
    // again after the cooldown.
    let kicked = false
    for (let attempt = 0; attempt < 10 && !kicked; attempt++) {
      await frames(() => {
        const present = runner.present as RoomSimulation
        const state = goalState(present)
        const disc = present.world.getPosition(state.players[me].disc)
        const ball = present.world.getPosition(state.ball)
        const gap = Math.hypot(ball.x - disc.x, ball.y - disc.y) - PLAYER_RADIUS - BALL_RADIUS
        return gap < KICK_REACH / 5 && present.tick - state.players[me].lastKick > 30
      }, 'the ball in reach')
      const present = runner.present as RoomSimulation
      const speedBefore = present.world.getLinearVelocity(goalState(present).ball).x
      const seq = runner.gameCommand('kick', { power: 1 }, performance.now())
      expect(goalState(runner.present).players[me].lastKick).toBe(runner.present?.tick)
      // KICK_IMPULSE / ball mass = 7.07 m/s more along the line of centres (mostly +x).
      expect(present.world.getLinearVelocity(goalState(present).ball).x).toBeGreaterThan(speedBefore + 5)
      expect(goalState(runner.sim).players[me].lastKick).toBe(-1)
      const refused = (): boolean => red.bot.received.some((m) => m.t === 'error' && m.seq === seq)
      await frames(
        () => goalState(runner.sim).players[me].lastKick >= 0 || refused(),
        `kick ${seq} confirmed or refused`,
      )
      kicked = goalState(runner.sim).players[me].lastKick >= 0
    }
    expect(kicked).toBe(true)
    console.log(`predict: ${JSON.stringify(runner.predict)}`)

    // Converged: with nothing pending, the present's hash at its tick is the confirmed one there,
    // and the confirmed simulation matched the server's checkpoints.
    runner.gameCommand('run', { x: 0, y: 0 }, performance.now())
    await frames(() => goalState(runner.sim).players[me].vx === 0, 'the stop confirmed')
    const samples: Array<[number, number]> = []
    for (let i = 0; i < 5; i++) {
      await frames(() => true, 'a frame')
      const present = runner.present as RoomSimulation
      samples.push([present.tick, present.hash()])
      await new Promise((r) => setTimeout(r, 50))
    }
    const last = Math.max(...samples.map(([t]) => t))
    await frames(
      () => (runner.sim?.tick ?? 0) >= last && runner.stats.hashesChecked >= 3,
      'the confirmed tick',
    )
    for (const [tick, hash] of samples) expect([tick, confirmed.get(tick)]).toEqual([tick, hash])
    expect(runner.stats.desyncs).toBe(0)
    await blue.close()
    await red.close()
  })
})
