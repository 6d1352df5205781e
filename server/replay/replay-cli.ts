/*
 * The replay tool:
 *   npm run replay -- FILE [--verify] [--to TICK] [--hash-every N] [--progress N] [--json] [--games DIR]
 * Rebuilds the world from the log's header, applies every record at its tick, checks every
 * recorded hash (with --verify also every keyframe), and prints ticks, duration, players,
 * commands and steps per second. With --progress N, a line `replay: tick T of L (P %)` goes to
 * standard error every N room ticks while it runs. A log of a game loaded with the server's --games
 * DIR needs the same --games DIR here (loaded and checked as the server does; without it the tool
 * says so in one line). Exit codes: 0 replayed and matched, 1 a hash
 * or keyframe differed (the first mismatch is printed), 2 bad usage or a file that is not a
 * readable log (one line, no stack trace), 3 replayed but the log's tail was torn or corrupt.
 */
import { readFile } from 'node:fs/promises'
import { hex } from '../../shared/index.ts'
import { addLoadedGames, GameLoadError, loadGameDirectory } from '../games/index.ts'
import { type ReplayOptions, ReplayToolError, replayLog, UnknownGameError } from './replay-tool.ts'

const USAGE =
  'usage: npm run replay -- FILE [--verify] [--to TICK] [--hash-every N] [--progress N] [--json] [--games DIR]'

function fail(message: string): never {
  process.stderr.write(`replay: ${message}\n`)
  process.exit(2)
}

function intArg(flag: string, raw: string | undefined): number {
  if (raw === undefined || !/^\d+$/.test(raw) || !Number.isSafeInteger(Number(raw)))
    fail(`${flag} needs a non-negative integer, got ${raw === undefined ? 'nothing' : `"${raw}"`}`)
  return Number(raw)
}

async function main(): Promise<void> {
  const argv = process.argv.slice(2)
  const options: ReplayOptions = {}
  let json = false
  let file: string | undefined
  let gamesDir: string | undefined
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i]
    if (a === '--verify') options.verify = true
    else if (a === '--json') json = true
    else if (a === '--to') options.to = intArg(a, argv[++i])
    else if (a === '--hash-every') options.hashEvery = intArg(a, argv[++i]) || undefined
    else if (a === '--progress') options.progressEvery = intArg(a, argv[++i])
    else if (a === '--games') {
      gamesDir = argv[++i]
      if (gamesDir === undefined || gamesDir.startsWith('--')) fail(`--games needs a directory; ${USAGE}`)
    } else if (a === '--help' || a === '-h') {
      process.stdout.write(`${USAGE}\n`)
      return
    } else if (a.startsWith('--')) fail(`unknown option ${a}; ${USAGE}`)
    else if (file === undefined) file = a
    else fail(`one log at a time; ${USAGE}`)
  }
  if (!file) fail(USAGE)
  let bytes: Uint8Array
  try {
    bytes = await readFile(file)
  } catch (error) {
    fail(`cannot read ${file}: ${(error as NodeJS.ErrnoException).code ?? (error as Error).message}`)
  }
  if (gamesDir !== undefined) {
    try {
      addLoadedGames(await loadGameDirectory(gamesDir))
    } catch (error) {
      if (error instanceof GameLoadError) fail(error.message)
      throw error
    }
  }
  // A long log replays for minutes (about 26x real time for an awake pyramid): --progress says how
  // far it got.
  options.onProgress = (tick, last) =>
    process.stderr.write(
      `replay: tick ${tick} of ${last} (${Math.floor((100 * tick) / Math.max(last, 1))} %)\n`,
    )
  let report: Awaited<ReturnType<typeof replayLog>>
  try {
    report = await replayLog(bytes, options)
  } catch (error) {
    if (error instanceof UnknownGameError)
      fail(
        `log ${file} was recorded with game "${error.game}": ${gamesDir === undefined ? 'load it with --games DIR' : `${gamesDir} has no game of that name`}`,
      )
    if (error instanceof ReplayToolError) fail(`${file}: ${error.message}`)
    fail(`${file}: ${(error as Error).message}`)
  }
  const d = report.divergence
  if (json) process.stdout.write(`${JSON.stringify(report)}\n`)
  else {
    const lines = [
      `log        ${file}`,
      `room       ${report.room} (scene ${report.scene}), started ${report.start}`,
      `ticks      ${report.firstTick} to ${report.lastTick}: ${report.ticks} ticks, ${report.seconds.toFixed(1)} s`,
      `players    ${report.players}`,
      `commands   ${report.commands}`,
      `hashes     ${report.hashesChecked} checked${options.verify ? `, ${report.keyframesChecked} keyframes checked` : ''}`,
      `speed      ${Math.round(report.stepsPerSecond)} steps/s, ${Math.round(report.ticksPerSecond)} ticks/s (${(report.ticksPerSecond / 60).toFixed(1)}x real time)`,
      `final hash ${hex(report.finalHash)}`,
      `log end    ${report.read.closed ? 'clean close' : `${report.read.state}${report.read.reason ? `: ${report.read.reason}` : ''}`}`,
    ]
    for (const h of report.hashes) lines.push(`tick ${h.tick} ${hex(h.hash)}`)
    if (d) lines.push(`MISMATCH at tick ${d.tick}: ${d.reason}`)
    process.stdout.write(`${lines.join('\n')}\n`)
  }
  if (d) {
    if (json) process.stderr.write(`replay: mismatch at tick ${d.tick}: ${d.reason}\n`)
    process.exit(1)
  }
  if (report.read.state === 'torn' || report.read.state === 'corrupt') process.exit(3)
}

main().catch((error) => fail((error as Error).message))
