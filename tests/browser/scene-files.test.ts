/*
 * Keep and share in real Chromium against a real server: Save downloads the room's world as a
 * scene file and makes a share link; the link opens the same bodies in a new room in a second
 * page; Open (the file picker) and a file dropped on the page open a file in a room; a file with
 * a bad field is refused in the page with the field named, before it reaches the server.
 */
import { mkdir, mkdtemp } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { parseScene } from '../../games/index.ts'
import { buildClient } from '../../scripts/build-client.mjs'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { bodies, loadScene, openSandbox, serveClient } from '../support/client-harness.ts'

const DIST = 'test-results/browser-scenes/dist'
let server: RunningServer
let browser: Browser
let base: string

beforeAll(async () => {
  await mkdir(DIST, { recursive: true })
  await buildClient(DIST)
  const sceneDir = await mkdtemp(join(tmpdir(), 'concord-page-scenes-'))
  ;[server, browser] = await Promise.all([serveClient(DIST, { sceneDir }), launchBrowser()])
  base = `http://127.0.0.1:${server.port}`
})

afterAll(async () => {
  await browser?.close()
  await server?.close()
})

const sceneOf = (page: Page): Promise<string> => page.evaluate(() => window.concord.sandbox.scene())
const toast = (page: Page): Promise<string> =>
  page.evaluate(() => document.getElementById('toast')?.textContent ?? '')

/** Bodies by position (mm), sorted: the same world whatever the ids. */
async function layout(page: Page): Promise<string[]> {
  return (await bodies(page))
    .map((b) => `${b.kind} ${Math.round(b.x * 1000)} ${Math.round(b.y * 1000)}`)
    .sort()
}

describe('keep and share', { timeout: 300_000 }, () => {
  it('saves a room as a file, opens its share link in a new room, and opens files picked or dropped', async () => {
    const { context, page, errors } = await openSandbox(browser, `${base}/?room=keep`)
    await loadScene(page, 'joints', 3)
    await page.evaluate(() => window.concord.sandbox.send({ k: 'pause', paused: true }))
    await page.waitForFunction(() => window.concord.sandbox.paused())
    const [download] = await Promise.all([page.waitForEvent('download'), page.click('#save-scene')])
    expect(download.suggestedFilename()).toBe('keep.json')
    const path = await download.path()
    const text = await (await import('node:fs/promises')).readFile(path, 'utf8')
    const parsed = parseScene(text)
    if (!parsed.ok) throw new Error(parsed.error)
    expect(parsed.scene.bodies.length).toBe((await bodies(page)).length)
    await page.waitForFunction(() => window.concord.sceneFiles.lastShareLink !== '')
    const link = await page.evaluate(() => window.concord.sceneFiles.lastShareLink)
    expect(link).toMatch(new RegExp(`^${base}/\\?scene=[0-9a-f]{16}$`))
    const id = link.slice(-16)
    // The notice says where the file went and gives the link (after any notice shown before it).
    await page.waitForFunction((l) => (document.getElementById('toast')?.textContent ?? '').includes(l), link)
    expect(await toast(page)).toMatch(/^Saved as keep\.json\. Share link/)
    const saved = await layout(page)

    // The share link: a second page, a new room of its own, the same bodies.
    const shared = await openSandbox(browser, link)
    await shared.page.waitForFunction((want) => window.concord.sandbox.scene() === want, `file:${id}`)
    const room = await shared.page.evaluate(() => new URLSearchParams(location.search).get('room') ?? '')
    expect(room).toMatch(new RegExp(`^s-${id.slice(0, 8)}-\\d{4}$`))
    await shared.page.evaluate(() => window.concord.sandbox.send({ k: 'pause', paused: true }))
    await shared.page.waitForFunction(() => window.concord.sandbox.paused())
    // Paused at once, the opened world has stepped at most a few ticks: compare the static layout
    // exactly and the count of everything.
    const opened = await layout(shared.page)
    expect(opened.length).toBe(saved.length)
    expect(opened.filter((b) => b.startsWith('0 '))).toEqual(saved.filter((b) => b.startsWith('0 ')))

    // Open: the file picker, in a third room.
    const picker = await openSandbox(browser, `${base}/?room=picked`)
    await picker.page.setInputFiles('#scene-file', {
      name: 'keep.json',
      mimeType: 'application/json',
      buffer: Buffer.from(text),
    })
    await picker.page.waitForFunction((want) => window.concord.sandbox.scene() === want, `file:${id}`)
    // A bad field is refused in the page, naming it, and the room keeps its world.
    const bad = text.replace('"type":"circle","radius":0.4', '"type":"circle","radius":0')
    expect(bad).not.toBe(text)
    await picker.page.setInputFiles('#scene-file', {
      name: 'bad.json',
      mimeType: 'application/json',
      buffer: Buffer.from(bad),
    })
    await picker.page.waitForFunction(() =>
      (document.getElementById('toast')?.textContent ?? '').includes('bad.json'),
    )
    expect(await toast(picker.page)).toMatch(
      /bad\.json is not a scene file Concord can open: bodies\[\d+\]\.shapes\[0\]\.radius must be > 0/,
    )
    expect(await sceneOf(picker.page)).toBe(`file:${id}`)

    // A file dropped on the page, in a fourth room.
    const dropped = await openSandbox(browser, `${base}/?room=dropped`)
    await dropped.page.evaluate((content) => {
      const data = new DataTransfer()
      data.items.add(new File([content], 'dropped.json', { type: 'application/json' }))
      window.dispatchEvent(new DragEvent('drop', { dataTransfer: data, bubbles: true, cancelable: true }))
    }, text)
    await dropped.page.waitForFunction((want) => window.concord.sandbox.scene() === want, `file:${id}`)

    for (const p of [errors, shared.errors, picker.errors, dropped.errors]) expect(p).toEqual([])
    await Promise.all([
      context.close(),
      shared.context.close(),
      picker.context.close(),
      dropped.context.close(),
    ])
  })

  it('saves from a lockstep page and opens a file in a predict page (the same buttons as snapshot pages)', async () => {
    const { context, page, errors } = await openSandbox(browser, `${base}/?room=keep-ls&mode=lockstep`)
    expect(await page.isVisible('#save-scene')).toBe(true)
    expect(await page.isVisible('#open-scene')).toBe(true)
    await page.evaluate(() => window.concord.sandbox.send({ k: 'scene', name: 'joints' }))
    await page.waitForFunction(() => window.concord.sandbox.scene() === 'joints')
    await page.evaluate(() => window.concord.sandbox.send({ k: 'pause', paused: true }))
    await page.waitForFunction(() => window.concord.sandbox.paused())
    const [download] = await Promise.all([page.waitForEvent('download'), page.click('#save-scene')])
    expect(download.suggestedFilename()).toBe('keep-ls.json')
    const text = await (await import('node:fs/promises')).readFile(await download.path(), 'utf8')
    const parsed = parseScene(text)
    if (!parsed.ok) throw new Error(parsed.error)
    const saved = await layout(page)
    expect(parsed.scene.bodies.length).toBe(saved.length)
    await page.waitForFunction(() => window.concord.sceneFiles.lastShareLink !== '')
    const id = (await page.evaluate(() => window.concord.sceneFiles.lastShareLink)).slice(-16)

    // Open: the file picker of a predict page, in a room of its own; the page gets the scene as a sync.
    const predict = await openSandbox(browser, `${base}/?room=picked-ls&mode=predict`)
    await predict.page.setInputFiles('#scene-file', {
      name: 'keep-ls.json',
      mimeType: 'application/json',
      buffer: Buffer.from(text),
    })
    await predict.page.waitForFunction((want) => window.concord.sandbox.scene() === want, `file:${id}`)
    await predict.page.evaluate(() => window.concord.sandbox.send({ k: 'pause', paused: true }))
    await predict.page.waitForFunction(() => window.concord.sandbox.paused())
    const opened = await layout(predict.page)
    expect(opened.length).toBe(saved.length)
    expect(opened.filter((b) => b.startsWith('0 '))).toEqual(saved.filter((b) => b.startsWith('0 ')))
    for (const p of [errors, predict.errors]) expect(p).toEqual([])
    await Promise.all([context.close(), predict.context.close()])
  })
})
