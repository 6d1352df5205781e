/*
 * The child process of `npm run bench:peers`: one engine, one scene, one sleep setting, so engines
 * never share a heap, a garbage collector, JIT state or a WebAssembly memory. The parent sends
 * commands over the IPC channel and waits for each answer, which is how it interleaves the
 * engines' chunks of steps.
 *
 * Commands: {type: 'build', engine, scene, count, sleep} -> {type: 'built', buildMs, baseRssMB};
 * {type: 'run', steps} -> {type: 'ran', times, cpuMs}; {type: 'finish'} -> {type: 'finished',
 * quality, peakRssMB}. CPU is process.cpuUsage() (user + system, every thread of the process)
 * around the chunk; peak memory is process.resourceUsage().maxRSS.
 */
import { benchScene } from './bench-scenes.ts'
import { PeerRun } from './peer-run.ts'
import { isPeerEngine } from './peers/index.ts'
import type { SceneQuality } from './scene-quality.ts'

/** A command from the parent. */
export type ChildCommand =
  | { type: 'build'; engine: string; scene: string; count: number; sleep: boolean }
  | { type: 'run'; steps: number }
  | { type: 'finish' }

/** An answer to the parent. */
export type ChildReply =
  | { type: 'built'; buildMs: number; baseRssMB: number; bodies: number }
  | { type: 'ran'; times: number[]; cpuMs: number }
  | { type: 'finished'; quality: SceneQuality; peakRssMB: number }
  | { type: 'error'; message: string }

const MB = 1024 * 1024
let run: PeerRun | null = null

function reply(message: ChildReply): void {
  process.send?.(message)
}

async function handle(command: ChildCommand): Promise<void> {
  if (command.type === 'build') {
    if (!isPeerEngine(command.engine)) throw new Error(`unknown engine ${JSON.stringify(command.engine)}`)
    const baseRssMB = process.memoryUsage.rss() / MB
    run = await PeerRun.start(command.engine, benchScene(command.scene), command.count, command.sleep)
    reply({ type: 'built', buildMs: run.buildMs, baseRssMB, bodies: run.dynamicBodies })
    return
  }
  if (run === null) throw new Error(`command ${command.type} before build`)
  if (command.type === 'run') {
    const times: number[] = []
    const cpu0 = process.cpuUsage()
    run.stepChunk(command.steps, times)
    const cpu = process.cpuUsage(cpu0)
    reply({ type: 'ran', times, cpuMs: (cpu.user + cpu.system) / 1000 })
    return
  }
  const quality = run.quality()
  run.dispose()
  reply({ type: 'finished', quality, peakRssMB: (process.resourceUsage().maxRSS * 1024) / MB })
}

process.on('message', (message: ChildCommand) => {
  handle(message).catch((error: unknown) => {
    reply({ type: 'error', message: error instanceof Error ? (error.stack ?? error.message) : String(error) })
  })
})
