/*
 * Simulated players for tests, benchmarks and load: a Node client of the protocol (BotClient, on the
 * shared ClientMirror), a lockstep or predicting bot (LockstepBot, on shared/sim's clients), and the
 * load bots' schedule and command line (bots.ts, `npm run bots`).
 */
export { BotClient } from './bot-client.ts'
export { botCommand, driveBot } from './bots.ts'
export { LockstepBot } from './lockstep-bot.ts'
