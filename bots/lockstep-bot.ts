/*
 * A lockstep (or predicting) client in Node: a BotClient joined with mode "lockstep" or
 * "predict" whose messages feed a LockstepClient / PredictClient (the same runner the page uses),
 * stepped from a timer as a page steps from requestAnimationFrame. Tests and benchmarks use it.
 */
import { performance } from 'node:perf_hooks'
import { findGame } from '../games/index.ts'
import { type GameCatalog, LockstepClient, PredictClient } from '../shared/index.ts'
import { BotClient, type BotOptions } from './bot-client.ts'

/** A lockstep client over a real socket. */
export class LockstepBot {
  readonly runner: LockstepClient
  private timer: NodeJS.Timeout | null = null

  private constructor(
    readonly bot: BotClient,
    mode: 'lockstep' | 'predict',
    hold: number | undefined,
    games: GameCatalog,
  ) {
    const send = bot.send.bind(bot)
    this.runner =
      mode === 'predict'
        ? new PredictClient({
            send,
            games,
            clock: () => performance.now(),
            ...(hold === undefined ? {} : { hold }),
          })
        : new LockstepClient({ send, games, ...(hold === undefined ? {} : { hold }) })
    bot.onServerMessage = (message) => this.runner.handle(message, performance.now())
  }

  /**
   * Connect, join and start stepping every `frameMs` (16 ms: a 60 Hz page). The join's hold is
   * `options.hold` when given, else the runner's own (lockstep 2, predict 30). `games` finds the
   * room's game by name (default: the games this build ships; a test of a game loaded with --games
   * passes its bundle's game).
   */
  static async connect(
    options: Omit<BotOptions, 'mode'>,
    mode: 'lockstep' | 'predict' = 'lockstep',
    frameMs = 16,
    games: GameCatalog = findGame,
  ): Promise<LockstepBot> {
    const bot = new BotClient({ ...options, mode })
    const client = new LockstepBot(bot, mode, options.hold, games)
    await bot.opened
    bot.join(undefined, client.runner.hold)
    await bot.waitFor(() => client.runner.playerId !== 0, 'welcome')
    client.timer = setInterval(() => client.frame(), frameMs)
    return client
  }

  /** One frame: simulate up to the playout target. */
  frame(): void {
    this.runner.advance(performance.now())
  }

  /** Resolve when `condition` holds, checked every frame; rejects after `timeoutMs` or on close. */
  waitFor(condition: () => boolean, what: string, timeoutMs = 120_000): Promise<void> {
    const start = performance.now()
    return new Promise((resolve, reject) => {
      const check = setInterval(() => {
        if (condition()) {
          clearInterval(check)
          resolve()
        } else if (this.bot.ws.readyState > 1 || performance.now() - start > timeoutMs) {
          clearInterval(check)
          const why = this.bot.ws.readyState > 1 ? `socket closed (${this.bot.closeCode})` : 'timed out'
          reject(
            new Error(`${why} waiting for ${what}; runner ${this.runner.state}, ${this.runner.lastProblem}`),
          )
        }
      }, 5)
    })
  }

  /** Stop stepping and close the socket. */
  async close(): Promise<void> {
    if (this.timer) clearInterval(this.timer)
    this.timer = null
    await this.bot.close()
  }
}
