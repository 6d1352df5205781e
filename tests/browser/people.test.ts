/*
 * The player list in real Chromium against a real server (issue 31, People): two pages in one
 * room list each other with "(you)" and the creator's star; one renames itself in the list's name
 * field and the other's list shows the new name; one grabs a body with the mouse and the other's
 * list says who holds which body. A lockstep page lists the same people and renames too.
 */
import { mkdir } from 'node:fs/promises'
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { buildClient } from '../../scripts/build-client.mjs'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { bodies, openSandbox, pressUntilGrabbed, serveClient } from '../support/client-harness.ts'

const DIST = 'test-results/browser-people/dist'
let server: RunningServer
let browser: Browser
let base: string

beforeAll(async () => {
  await mkdir(DIST, { recursive: true })
  await buildClient(DIST)
  // Rooms on the main thread: the restored-notice case sets a room's notice directly.
  ;[server, browser] = await Promise.all([
    serveClient(DIST, { defaultScene: 'tower', workers: 0 }),
    launchBrowser(),
  ])
  base = `http://127.0.0.1:${server.port}`
})

afterAll(async () => {
  await browser?.close()
  await server?.close()
})

/** The player list's lines as the page shows them. */
const listed = (page: Page): Promise<string[]> =>
  page.evaluate(() => [...document.querySelectorAll('#people-list li')].map((li) => li.textContent ?? ''))

/** Wait until the page's player list shows exactly `want` (in id order). */
async function waitForList(page: Page, want: string[]): Promise<void> {
  await page
    .waitForFunction(
      (w) =>
        JSON.stringify([...document.querySelectorAll('#people-list li')].map((li) => li.textContent)) ===
        JSON.stringify(w),
      want,
      { timeout: 60_000 },
    )
    .catch(async (error) => {
      throw new Error(`${(error as Error).message}: the list shows ${JSON.stringify(await listed(page))}`)
    })
}

describe('the player list', { timeout: 300_000 }, () => {
  it('shows who is here, a rename made in the other page, and who holds which body', async () => {
    const a = await openSandbox(browser, `${base}/?room=people&name=Ana`)
    const b = await openSandbox(browser, `${base}/?room=people&name=Bo`)
    await waitForList(a.page, ['Ana (you) ★ creator', 'Bo'])
    await waitForList(b.page, ['Ana ★ creator', 'Bo (you)'])
    expect(await b.page.isVisible('#people')).toBe(true)
    expect(await b.page.inputValue('#my-name')).toBe('Bo')

    // Rename in the page: type and press Enter; the other page's list follows.
    await a.page.fill('#my-name', 'Ana Lima')
    await a.page.press('#my-name', 'Enter')
    await waitForList(b.page, ['Ana Lima ★ creator', 'Bo (you)'])
    await waitForList(a.page, ['Ana Lima (you) ★ creator', 'Bo'])
    // The Rename button works as well, from the second page.
    await b.page.fill('#my-name', 'Bo Chen')
    await b.page.click('#rename')
    await waitForList(a.page, ['Ana Lima (you) ★ creator', 'Bo Chen'])

    // Ana grabs a tower block with the mouse; Bo's list says she holds it.
    const block = (await bodies(a.page)).filter((v) => v.kind === 2).sort((p, q) => q.y - p.y)[0]
    await pressUntilGrabbed(a.page, block.id)
    await waitForList(b.page, [`Ana Lima ★ creator holds body ${block.id}`, 'Bo Chen (you)'])
    await waitForList(a.page, [`Ana Lima (you) ★ creator holds body ${block.id}`, 'Bo Chen'])
    await a.page.mouse.up()
    await waitForList(b.page, ['Ana Lima ★ creator', 'Bo Chen (you)'])

    // A lockstep page in the same room lists everyone and renames too.
    const c = await openSandbox(browser, `${base}/?room=people&name=Cy&mode=lockstep`)
    await waitForList(c.page, ['Ana Lima ★ creator', 'Bo Chen', 'Cy (you)'])
    await c.page.fill('#my-name', 'Cy Rao')
    await c.page.press('#my-name', 'Enter')
    await waitForList(a.page, ['Ana Lima (you) ★ creator', 'Bo Chen', 'Cy Rao'])

    for (const p of [a, b, c]) expect(p.errors).toEqual([])
    await Promise.all([a.context.close(), b.context.close(), c.context.close()])
  })

  it("shows a reopened room's notice to whoever joins it, in snapshot and lockstep pages", async () => {
    // What crash recovery or a planned restart sets on a room it reopened (planned-restart.test.ts
    // checks the server side with a real restart); here the page's side.
    const text = 'This room was restored after a server restart: what was built here is back.'
    for (const [room, mode] of [
      ['restored', ''],
      ['restored-lockstep', '&mode=lockstep'],
    ]) {
      // A room of its own for each page: a room its players left untouched is disposed at the
      // next once-a-second check, so a second page in the first page's room could find a fresh
      // room without the notice. A room opened without players waits --room-idle-seconds (60 s).
      const opened = server.rooms.getOrCreate(room)
      if (!opened) throw new Error(`no room ${room}`)
      opened.notice = text
      const p = await openSandbox(browser, `${base}/?room=${room}&name=Di${mode}`)
      // The notice reaches the page's notices (shown as a toast for a few seconds: it may be gone
      // by the time the page is ready, so the notice list is what is read).
      // Another notice may follow it on a loaded machine: look among the last three.
      await p.page.waitForFunction((t) => window.concord.sandbox.notices().recent?.includes(t), text)
      expect(p.errors).toEqual([])
      await p.context.close()
    }
  })
})
