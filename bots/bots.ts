/*
 * Load bots: `npm run bots -- --url ws://127.0.0.1:8080 --room NAME --count N [--seconds S]`.
 * Each bot joins, spawns a few shapes, then repeatedly grabs a random body and drags it in a
 * circle, releasing and regrabbing now and then. Every second it prints per-bot RTT and received
 * bytes per second. Runs until --seconds elapse (0 = forever) or Ctrl-C.
 */
import { performance } from 'node:perf_hooks'
import { Prng } from '../engine/index.ts'
import type { Command, WireShape } from '../shared/index.ts'
import { BotClient } from './bot-client.ts'

interface BotArgs {
  url: string
  room: string
  count: number
  seconds: number
  /** Spread the bots over this many rooms, named ROOM-1 ... ROOM-K (1 = just ROOM). */
  rooms: number
}

/** `npm run bots -- --help`: the options, their defaults and meanings, in aligned columns. */
export function botsHelp(): string {
  const rows = [
    ['option', 'default', 'meaning'],
    ['--url <ws url>', 'ws://127.0.0.1:8080', 'the server (its WebSocket base URL)'],
    ['--room <name>', 'lobby', 'the room the bots join'],
    ['--count <n>', '4', 'how many bots, 1..1000'],
    ['--seconds <s>', '0', 'stop after this long (0 = run until Ctrl-C)'],
    ['--rooms <k>', '1', 'spread the bots over k rooms named ROOM-1 .. ROOM-k'],
    ['--help', '', 'this text'],
  ]
  const widths = [0, 1].map((c) => Math.max(...rows.map((r) => r[c].length)))
  return [
    'Usage: npm run bots -- [options]',
    'Simulated players: each joins, spawns a few shapes, then grabs bodies and drags them in circles,',
    'printing its round-trip time and received bytes every second.',
    '',
    ...rows.map((r) => `  ${r[0].padEnd(widths[0])}  ${r[1].padEnd(widths[1])}  ${r[2]}`),
  ].join('\n')
}

/** The bots' options from the command line, or 'help' for --help / -h; throws naming a bad option. */
export function parseArgs(argv: string[]): BotArgs | 'help' {
  if (argv.includes('--help') || argv.includes('-h')) return 'help'
  const args: BotArgs = { url: 'ws://127.0.0.1:8080', room: 'lobby', count: 4, seconds: 0, rooms: 1 }
  for (let i = 0; i < argv.length; i += 2) {
    const [flag, value] = [argv[i], argv[i + 1]]
    if (value === undefined) throw new Error(`${flag} needs a value`)
    if (flag === '--url') args.url = value
    else if (flag === '--room') args.room = value
    else if (flag === '--count') args.count = Number.parseInt(value, 10)
    else if (flag === '--seconds') args.seconds = Number(value)
    else if (flag === '--rooms') args.rooms = Number.parseInt(value, 10)
    else throw new Error(`unknown option ${flag}; use --url, --room, --count, --seconds, --rooms (--help)`)
  }
  if (!(args.count >= 1 && args.count <= 1000)) throw new Error('--count must be 1..1000')
  return args
}

/**
 * The bots' schedule: the command for step `step` (0, 1, ...) of a bot's own 20 Hz loop, or null.
 * Steps 0-2 spawn a circle, box or triangle; then every 100 steps the bot grabs a random body of
 * `dynamic()` (dynamic body ids), drags it round a circle for 79 steps and releases it. The load
 * bots here and the benchmarks that simulate players in-process (bench/room-tick-bench.ts,
 * bench/alloc-bench.ts) all follow it.
 */
export function botCommand(prng: Prng, step: number, dynamic: () => number[]): Command | null {
  if (step < 3) {
    const kind = prng.int(3)
    const shape: WireShape =
      kind === 0
        ? { type: 'circle', radius: 0.3 + prng.next() * 0.3 }
        : kind === 1
          ? { type: 'box', hw: 0.3 + prng.next() * 0.3, hh: 0.3 + prng.next() * 0.3 }
          : { type: 'polygon', v: [-0.4, -0.3, 0.4, -0.3, 0, 0.5] }
    return { k: 'spawn', shape, x: prng.next() * 10 - 5, y: 8 + prng.next() * 4 }
  }
  const phase = step % 100
  if (phase === 0) {
    const ids = dynamic()
    return ids.length > 0 ? { k: 'grab', body: ids[prng.int(ids.length)], lx: 0, ly: 0 } : null
  }
  if (phase === 80) return { k: 'release' }
  if (phase > 80) return null
  const a = (phase / 80) * 2 * Math.PI
  return { k: 'move', x: 4 * Math.cos(a), y: 6 + 3 * Math.sin(a) }
}

/** One bot's behaviour for one tick of its own 20 Hz loop. */
export function driveBot(bot: BotClient, prng: Prng, step: number): void {
  const cmd = botCommand(prng, step, () =>
    [...bot.mirror.bodies.values()].filter((b) => b.kind === 2).map((b) => b.id),
  )
  if (cmd) bot.command(cmd)
}

async function main(): Promise<void> {
  const args = parseArgs(process.argv.slice(2))
  if (args === 'help') {
    process.stdout.write(`${botsHelp()}\n`)
    return
  }
  const url = args.url.replace(/^ws/, 'http')
  const bots: BotClient[] = []
  const roomOf = (i: number): string => (args.rooms > 1 ? `${args.room}-${(i % args.rooms) + 1}` : args.room)
  for (let i = 0; i < args.count; i++) {
    bots.push(await BotClient.connect({ url, room: roomOf(i), name: `bot ${i + 1}` }))
  }
  const where = args.rooms > 1 ? `${args.rooms} rooms ${args.room}-1..${args.rooms}` : `room ${args.room}`
  process.stdout.write(`${bots.length} bots joined ${where}\n`)
  const prngs = bots.map((_, i) => new Prng(i + 1))
  let step = 0
  const drive = setInterval(() => {
    step++
    bots.forEach((b, i) => {
      driveBot(b, prngs[i], step)
    })
  }, 50)
  let lastBytes = bots.map((b) => b.bytesReceived)
  let last = performance.now()
  const report = setInterval(() => {
    const now = performance.now()
    const seconds = (now - last) / 1000
    last = now
    const rates = bots.map((b, i) => (b.bytesReceived - lastBytes[i]) / seconds)
    const lines = bots.map((b, i) => {
      b.ping()
      return `bot ${i + 1}: rtt ${Number.isNaN(b.rtt) ? '-' : b.rtt.toFixed(1)} ms, ${(rates[i] / 1000).toFixed(2)} kB/s, bodies ${b.mirror.bodies.size}`
    })
    lastBytes = bots.map((b) => b.bytesReceived)
    if (bots.length <= 10) process.stdout.write(`${lines.join('\n')}\n`)
    else {
      const rtts = bots.map((b) => b.rtt).filter((r) => !Number.isNaN(r))
      const mean = (xs: number[]): number => xs.reduce((a, b) => a + b, 0) / Math.max(1, xs.length)
      process.stdout.write(
        `${bots.length} bots: rtt mean ${mean(rtts).toFixed(1)} ms max ${Math.max(0, ...rtts).toFixed(1)} ms, ` +
          `received mean ${(mean(rates) / 1000).toFixed(2)} kB/s per bot\n`,
      )
    }
  }, 1000)
  const stop = async (): Promise<void> => {
    clearInterval(drive)
    clearInterval(report)
    await Promise.all(bots.map((b) => b.close()))
    process.exit(0)
  }
  process.once('SIGINT', stop)
  process.once('SIGTERM', stop)
  if (args.seconds > 0) setTimeout(stop, args.seconds * 1000)
  for (const b of bots)
    b.closed.then(() =>
      process.stdout.write(`bot ${b.mirror.clientId} closed: ${b.closeCode} ${b.closeReason}\n`),
    )
}

if (process.argv[1]?.endsWith('bots.ts') || process.argv[1]?.endsWith('bots.js')) {
  main().catch((error) => {
    process.stderr.write(`bots: ${(error as Error).message}\n`)
    process.exit(1)
  })
}
