/*
 * The same golden hash in Node and in headless Chromium, and the same vocabulary-scene hashes in
 * Node, Chromium and Firefox ESR.
 *
 * engine-page.ts (the engine plus the mixed scene of tests/engine/determinism-fixtures.ts) is
 * bundled for the browser with esbuild, injected into a blank page in Debian's Chromium (driven by
 * playwright-core, fresh temporary profile), and run there. The page's hashes every 100 steps must
 * equal Node's, and the one at step 600 must equal the pinned GOLDEN_HASH. The engine's own
 * sin/cos/atan2 must give the same bits in both; the host's Math.sin/cos/atan2 may differ, and the
 * test prints on how many of the inputs they do (the reason the engine carries its own trig).
 *
 * The vocabulary scene (determinism-fixtures.ts buildVocabularyScene: compound bodies, capsules,
 * segments, rounded polygons, decompose()d outlines, filters with a run-time change, sensors,
 * rolling resistance, conveyors, explosions) runs 3,000 steps; every 500 steps the world's hash and
 * a hash of every step's contact and sensor events and World query results (castRayClosest,
 * castRay, castShape, overlapAABB, overlapPoint, overlapShape) must be the same in Node, in
 * Chromium and in Debian's Firefox ESR (SpiderMonkey; skipped, with the reason printed, when it is
 * not installed).
 */
import { build } from 'esbuild'
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { GOLDEN_HASH, hex } from '../engine/determinism-fixtures.ts'
import { launchBrowser } from '../support/chromium.ts'
import { firefoxMissing, launchFirefox } from '../support/firefox.ts'
import { type EngineCheck, runGolden, runMachines, runVocabularyScene, trigReport } from './engine-page.ts'

let browser: Browser
let page: Page

/** engine-page.ts bundled for a browser page. */
async function pageBundle(): Promise<string> {
  const bundle = await build({
    entryPoints: [new URL('./engine-page.ts', import.meta.url).pathname],
    bundle: true,
    platform: 'browser',
    format: 'iife',
    target: 'es2022',
    write: false,
  })
  return bundle.outputFiles[0].text
}

/** Node's vocabulary-scene hashes, computed once for both browsers. */
let nodeVocabulary: number[] | null = null
function vocabularyInNode(): number[] {
  nodeVocabulary ??= runVocabularyScene()
  return nodeVocabulary
}

beforeAll(async () => {
  const code = await pageBundle()
  browser = await launchBrowser()
  page = await browser.newPage()
  const errors: string[] = []
  page.on('pageerror', (e) => errors.push(e.message))
  await page.setContent(
    '<!doctype html><html><head><title>engine determinism</title></head><body></body></html>',
  )
  await page.addScriptTag({ content: code })
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

  it('computes the same vocabulary-scene hashes as Node (new shape kinds, filters, sensors, surfaces, events, queries)', async () => {
    const pageHashes = await inPage((check) => check.runVocabularyScene())
    const nodeHashes = vocabularyInNode()
    console.log(
      `vocabulary: chromium ${pageHashes.map(hex).join(' ')}; node ${nodeHashes.map(hex).join(' ')}`,
    )
    expect(pageHashes.map(hex)).toEqual(nodeHashes.map(hex))
  }, 120_000)

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

const missingFirefox = firefoxMissing()
if (missingFirefox) console.warn(`engine-determinism.test.ts: the Firefox part is skipped: ${missingFirefox}`)

describe.skipIf(missingFirefox !== '')('the engine in Firefox ESR', () => {
  it('computes the same vocabulary-scene hashes as Node and Chromium', async () => {
    const firefox = await launchFirefox()
    try {
      const ffPage = await firefox.newPage()
      const errors: string[] = []
      ffPage.on('pageerror', (e) => errors.push(e instanceof Error ? e.message : String(e)))
      await ffPage.setContent(
        '<!doctype html><html><head><title>engine determinism</title></head><body></body></html>',
      )
      await ffPage.addScriptTag({ content: await pageBundle() })
      const agent = (await ffPage.evaluate('navigator.userAgent')) as string
      expect(agent).toMatch(/Firefox\//)
      const pageHashes = (await ffPage.evaluate(
        '(globalThis.concordEngineCheck.runVocabularyScene())',
      )) as number[]
      const nodeHashes = vocabularyInNode()
      console.log(
        `vocabulary: firefox (${agent.match(/Firefox\/[\d.]+/)?.[0]}) ${pageHashes.map(hex).join(' ')}; node ${nodeHashes.map(hex).join(' ')}`,
      )
      expect(errors).toEqual([])
      expect(pageHashes.map(hex)).toEqual(nodeHashes.map(hex))
    } finally {
      await firefox.close()
    }
  }, 300_000)
})
