/*
 * Test helpers for lockstep over real sockets: snapshot-mode bots driven by the scripted Activity
 * (so lockstep and snapshot players share each room), and a server clock the test drives faster
 * than real time. Driving the clock is test-only: the server's own TickClock is stopped and the
 * test calls RoomManager.tickAll() from a timer; nothing in the product changes.
 */
import { BotClient } from '../../bots/bot-client.ts'
import type { RunningServer } from '../../server/server.ts'
import { Activity } from './lockstep-activity.ts'

/** Snapshot-mode bots acting every `everyMs`. */
export class ActiveBots {
  private timer: NodeJS.Timeout | null = null

  private constructor(readonly bots: Array<{ bot: BotClient; activity: Activity }>) {}

  /** Join `count` bots to `room` and start them. */
  static async start(url: string, room: string, count: number, everyMs = 20, seed = 1): Promise<ActiveBots> {
    const bots = []
    for (let i = 0; i < count; i++) {
      const bot = await BotClient.connect({ url, room, name: `bot ${i + 1}` })
      bots.push({ bot, activity: new Activity(seed * 100 + i) })
    }
    const active = new ActiveBots(bots)
    active.timer = setInterval(() => active.act(), everyMs)
    return active
  }

  private act(): void {
    for (const { bot, activity } of this.bots) {
      const m = bot.mirror
      const cmd = activity.next({
        dynamicBodies: () => [...m.bodies.values()].filter((b) => b.kind === 2).map((b) => b.id),
        userJoints: () => [...m.joints.keys()],
      })
      if (cmd) bot.command(cmd)
    }
  }

  /** One bot sends a command now (a scene load, say). */
  command(index: number, cmd: Parameters<BotClient['command']>[0]): void {
    this.bots[index].bot.command(cmd)
  }

  /** Stop acting and close every bot. */
  async stop(): Promise<void> {
    if (this.timer) clearInterval(this.timer)
    this.timer = null
    await Promise.all(this.bots.map((b) => b.bot.close()))
  }
}

/** Run the server's rooms from a timer at `ticksPerSecond` instead of its 60 Hz clock (rooms on the main thread). */
export function driveClock(server: RunningServer, ticksPerSecond: number): () => void {
  if (server.pool)
    throw new Error('driveClock needs the rooms on the main thread: start the server with inProcessRooms')
  server.rooms.clock.stop()
  const start = performance.now()
  let ran = 0
  const timer = setInterval(() => {
    const due = Math.floor(((performance.now() - start) * ticksPerSecond) / 1000)
    // At most 8 ticks per wake-up: on a loaded machine the test slows down instead of bursting.
    for (let k = 0; k < 8 && ran < due; k++, ran++) server.rooms.tickAll()
    if (due - ran > 8) ran = due - 8
  }, 2)
  return () => clearInterval(timer)
}
