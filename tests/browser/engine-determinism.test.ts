/*
 * The same golden hash in Node and in headless Chromium.
 *
 * engine-page.ts (the engine plus the mixed scene of tests/engine/determinism-fixtures.ts) is
 * bundled for the browser with esbuild, injected into a blank page in Debian's Chromium (driven by
 * playwright-core, fresh temporary profile), and run there. The page's hashes every 100 steps must
 * equal Node's, and the one at step 600 must equal the pinned GOLDEN_HASH. The engine's own
 * sin/cos/atan2 must give the same bits in both; the host's Math.sin/cos/atan2 may differ, and the
 * test prints on how many of the inputs they do (the reason the engine carries its own trig).
 */
import { build } from 'esbuild'
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { GOLDEN_HASH, hex } from '../engine/determinism-fixtures.ts'
import { launchBrowser } from '../support/chromium.ts'
import { type EngineCheck, runGolden, runMachines, trigReport } from './engine-page.ts'

let browser: Browser
let page: Page

beforeAll(async () => {
  const bundle = await build({
    entryPoints: [new URL('./engine-page.ts', import.meta.url).pathname],
    bundle: true,
    platform: 'browser',
    format: 'iife',
    target: 'es2022',
    write: false,
  })
  browser = await launchBrowser()
  page = await browser.newPage()
  const errors: string[] = []
  page.on('pageerror', (e) => errors.push(e.message))
  await page.setContent(
    '<!doctype html><html><head><title>engine determinism</title></head><body></body></html>',
  )
  await page.addScriptTag({ content: bundle.outputFiles[0].text })
  const ready = await page.evaluate(
    () => typeof (globalThis as unknown as { concordEngineCheck?: unknown }).concordEngineCheck,
  )
  expect(errors).toEqual([])
  expect(ready).toBe('object')
}, 120_000)

afterAll(async () => {
  await browser?.close()
})

function inPage<T>(f: (check: EngineCheck) => T): Promise<T> {
  return page.evaluate((source) => {
    const check = (globalThis as unknown as { concordEngineCheck: EngineCheck }).concordEngineCheck
    return new Function('check', `return (${source})(check)`)(check)
  }, f.toString())
}

describe('the engine in headless Chromium', () => {
  it('runs in a real Chromium', async () => {
    const agent = await page.evaluate(() => navigator.userAgent)
    console.log(`browser: ${browser.version()} (${agent})`)
    expect(agent).toMatch(/Chrom/)
  })

  it('computes the same mixed-scene hashes as Node every 100 steps, and the golden hash at step 600', async () => {
    const pageHashes = await inPage((check) => check.runGolden())
    const nodeHashes = runGolden()
    console.log(`page hashes ${pageHashes.map(hex).join(' ')}; node ${nodeHashes.map(hex).join(' ')}`)
    expect(pageHashes.map(hex)).toEqual(nodeHashes.map(hex))
    expect(hex(pageHashes[pageHashes.length - 1]), `set GOLDEN_HASH if the engine changed on purpose`).toBe(
      hex(GOLDEN_HASH),
    )
  })

  it('computes the same machines-scene hashes as Node (every joint kind, springs, motors, a break)', async () => {
    const pageHashes = await inPage((check) => check.runMachines())
    const nodeHashes = runMachines()
    console.log(`machines: page ${pageHashes.map(hex).join(' ')}; node ${nodeHashes.map(hex).join(' ')}`)
    expect(pageHashes.map(hex)).toEqual(nodeHashes.map(hex))
  })

  it("gives the engine's sin, cos and atan2 the same bits as Node on 4,000 inputs; reports where Math differs", async () => {
    const inPageReport = await inPage((check) => check.trigReport())
    const nodeReport = trigReport()
    expect(inPageReport.inputs).toBe(nodeReport.inputs)
    expect(hex(inPageReport.sin)).toBe(hex(nodeReport.sin))
    expect(hex(inPageReport.cos)).toBe(hex(nodeReport.cos))
    expect(hex(inPageReport.atan2)).toBe(hex(nodeReport.atan2))
    const differing = (a: number[], b: number[]) => a.filter((x, i) => !Object.is(x, b[i])).length
    const n = nodeReport.mathSin.length
    console.log(
      `Math differs between Node ${process.version} and Chromium ${browser.version()} on ` +
        `sin ${differing(inPageReport.mathSin, nodeReport.mathSin)}/${n}, ` +
        `cos ${differing(inPageReport.mathCos, nodeReport.mathCos)}/${n}, ` +
        `atan2 ${differing(inPageReport.mathAtan2, nodeReport.mathAtan2)}/${n} inputs`,
    )
  })
})
