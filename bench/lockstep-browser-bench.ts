/*
 * Lockstep benchmark in Chromium (npm run bench:lockstep-browser): numbers printed and saved to
 * bench/results/lockstep-browser.json, not pass/fail. Debian's Chromium through playwright-core.
 *
 * Part 1, rollback cost in the browser: rollback-cost.ts (copy the confirmed simulation and
 * re-simulate 4, 8, 16 ticks in the 210-box pyramid and the 1,000-body pile) bundled into a page,
 * medians of REPS runs; bench:lockstep measures the same code in Node.
 *
 * Part 2, pointer to screen: the sandbox page built and served by a real server on 127.0.0.1 on its
 * own 60 Hz clock, reached through a TCP proxy that adds DELAY_MS in each direction
 * (latency-proxy.ts; the product is unchanged). In snapshot mode and in predict mode, grab-latency.ts
 * moves the pointer TRIALS times and times each move until the grabbed box has moved 1 CSS px on
 * screen. The snapshot page draws its own grabbed body shifted by the pointer's lead over the
 * server's cursor (online-sandbox.ts predictOwnGrab), a visual offset, not physics; so snapshot mode
 * is measured twice: as shipped, and with that shift switched off in the bench's page, which times
 * the server's simulated motion reaching the screen (what collisions and other players show).
 * Also measured without the proxy's delay (0 ms) for reference. The rollback cost is measured in
 * Node in the same run for a like-for-like comparison on this shared machine.
 * Flags: --quick (8 trials per mode, 5 rollback runs).
 */
import { build } from 'esbuild'
import { launchBrowser } from '../tests/support/chromium.ts'
import { openSandbox, startClientServer } from '../tests/support/client-harness.ts'
import { type GrabLatency, measureGrabLatency } from './grab-latency.ts'
import { startLatencyProxy } from './latency-proxy.ts'
import { formatRollbackCost, measureRollbackScenes, type RollbackCost } from './rollback-cost.ts'
import { machineInfo, saveResults } from './stats.ts'

const quick = process.argv.includes('--quick')
const REPS = quick ? 5 : 25
const TRIALS = quick ? 8 : 25
const DELAY_MS = 50
/** snapshot: the page as shipped; snapshot-physics: without its visual grab shift; predict. */
const MODES = ['snapshot', 'snapshot-physics', 'predict'] as const

async function rollbackInChromium(): Promise<Record<string, RollbackCost>> {
  const code = await build({
    entryPoints: [new URL('./rollback-cost-page.ts', import.meta.url).pathname],
    bundle: true,
    platform: 'browser',
    format: 'iife',
    target: 'es2022',
    write: false,
  })
  const browser = await launchBrowser()
  try {
    const page = await browser.newPage()
    await page.goto('about:blank')
    await page.addScriptTag({ content: code.outputFiles[0].text })
    const result = (await page.evaluate(`globalThis.concordRollbackBench(${REPS})`)) as Record<
      string,
      RollbackCost
    >
    const version = browser.version()
    for (const [name, r] of Object.entries(result))
      console.log(formatRollbackCost(`Chromium ${version}`, name, r))
    return result
  } finally {
    await browser.close()
  }
}

async function pointerToScreen(): Promise<Record<string, GrabLatency>> {
  const server = await startClientServer()
  const browser = await launchBrowser()
  const out: Record<string, GrabLatency> = {}
  try {
    for (const delay of [DELAY_MS, 0]) {
      const proxy = await startLatencyProxy(server.port, delay)
      try {
        for (const mode of MODES) {
          const room = `latency-${mode}-${delay}`
          const query = mode === 'predict' ? `room=${room}&mode=predict` : `room=${room}`
          const url = `http://127.0.0.1:${proxy.port}/?${query}`
          const { page, context, errors } = await openSandbox(browser, url)
          // Bench-only: the snapshot page's visual shift of its own grabbed body switched off in
          // this page, to time the server's simulated motion reaching the screen.
          if (mode === 'snapshot-physics')
            await page.evaluate('window.concord.sandbox.predictOwnGrab = () => {}')
          const r = await measureGrabLatency(page, TRIALS)
          const hud = (await page.evaluate(`document.getElementById('hud')?.textContent ?? ''`)) as string
          if (errors.length > 0) throw new Error(`${mode} page errors: ${errors.join('; ')}`)
          await context.close()
          out[`${mode}${delay}ms`] = r
          console.log(
            `pointer to screen, ${mode}, ${delay} ms added each way: median ${r.medianMs.toFixed(1)} ms ` +
              `(${r.medianFrames} frames), p95 ${r.p95Ms.toFixed(1)} ms, min ${r.minMs.toFixed(1)}, ` +
              `max ${r.maxMs.toFixed(1)} over ${r.trials} moves` +
              (mode === 'predict' ? `; HUD: ${hud.replace(/\s+/g, ' ').trim()}` : ''),
          )
        }
      } finally {
        await proxy.close()
      }
    }
  } finally {
    await browser.close()
    await server.close()
  }
  return out
}

const machine = machineInfo()
const rollbackNode = measureRollbackScenes(REPS)
for (const [name, r] of Object.entries(rollbackNode)) console.log(formatRollbackCost('Node', name, r))
const rollbackChromium = await rollbackInChromium()
const pointer = await pointerToScreen()
const file = `bench/results/lockstep-browser${quick ? '-quick' : ''}.json`
saveResults(file, {
  machine,
  addedDelayMsEachWay: DELAY_MS,
  rollbackNode,
  rollbackChromium,
  pointerToScreen: pointer,
  loadAfter: machineInfo().loadAverage,
})
console.log(`saved ${file}`)
process.exit(0)
