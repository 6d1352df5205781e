/*
 * The page's player list (issue 31, People; docs/client.md): everyone in the room with their
 * colour and name, "you" beside this page's player, a star beside the room's creator (who may lock
 * the room controls), and what each one holds ("holds body 12"; the body itself is drawn outlined
 * in the holder's colour). This page's player renames itself in the name field (Enter or Rename):
 * the room command `rename` (PROTOCOL.md "Room commands"), after which every page's list shows the
 * new name; the name is also remembered for this browser's next visit (main.ts reads it). Hidden
 * offline and in replays (the sandbox has no people()).
 */
import { MAX_NAME_LENGTH } from '../shared/index.ts'
import type { PersonRow, Sandbox } from './modes/index.ts'

const $ = <T extends HTMLElement = HTMLElement>(id: string): T => document.getElementById(id) as T

/** Where the page keeps the name its player last chose (localStorage key). */
export const NAME_KEY = 'concord.name'

/** One list line's text: name, "(you)", the creator's star, and what the player holds. */
export function personText(p: PersonRow): string {
  const parts = [p.name]
  if (p.self) parts.push('(you)')
  if (p.creator) parts.push('★ creator')
  if (p.holds !== 0) parts.push(`holds body ${p.holds}`)
  return parts.join(' ')
}

/** The player list panel (#people). */
export class PlayerList {
  /** What the list shows now, to rebuild it only when something changed. */
  private shown = ''

  constructor(
    private readonly sandbox: Sandbox,
    private readonly notify: (text: string) => void,
  ) {
    const online = typeof sandbox.people === 'function' && typeof sandbox.roomCommand === 'function'
    $('people').hidden = !online
    if (!online) return
    // Phones: start folded (the list is one tap away) so it does not cover the view.
    if (window.matchMedia('(max-width: 640px)').matches) $<HTMLDetailsElement>('people').open = false
    const field = $<HTMLInputElement>('my-name')
    field.maxLength = MAX_NAME_LENGTH
    $('rename').addEventListener('click', () => this.rename())
    // (The page's shortcuts ignore keys typed into a field.)
    field.addEventListener('keydown', (e) => e.key === 'Enter' && this.rename())
  }

  /** Send the name field's name (the server checks it as a join name and answers a refusal). */
  private rename(): void {
    const field = $<HTMLInputElement>('my-name')
    const name = field.value.trim()
    if (name === '') {
      this.notify('Type a name first.')
      return
    }
    const seq = this.sandbox.roomCommand?.('rename', { name })
    if (seq === null || seq === undefined) {
      this.notify('Renaming needs a connection to the server.')
      return
    }
    field.blur()
    try {
      localStorage.setItem(NAME_KEY, name)
    } catch {}
  }

  /** Once a frame: rebuild the list when a name, the creator or a hold changed. */
  update(): void {
    const rows = this.sandbox.people?.()
    if (!rows) return
    const key = rows.map((p) => `${p.id}\u0000${p.color}\u0000${personText(p)}`).join('\u0001')
    if (key === this.shown) return
    this.shown = key
    $('people-count').textContent = String(rows.length)
    const list = $('people-list')
    list.replaceChildren(
      ...rows.map((p) => {
        const li = document.createElement('li')
        li.dataset.player = String(p.id)
        const swatch = document.createElement('span')
        swatch.className = 'swatch'
        swatch.style.background = p.color
        li.append(swatch, personText(p))
        return li
      }),
    )
    const self = rows.find((p) => p.self)
    const field = $<HTMLInputElement>('my-name')
    if (self && document.activeElement !== field) field.value = self.name
  }
}
