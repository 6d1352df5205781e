/*
 * Scene files in the page (docs/scene-format.md, docs/client.md "Keep and share"):
 * - Save: the room saves its world on the server (the saveScene room command); the page then
 *   downloads the file (GET /scenes/ID) and offers a share link, `/?scene=ID`, copied to the
 *   clipboard where the browser allows.
 * - Open: a picked or dropped .json file is size-checked and validated here first (the same
 *   checker as the server: errors name the field), then kept on the server (POST /scenes) and
 *   opened in this room (the openScene room command; a room control).
 * - A share link opens the scene in a new room of its own (main.ts picks the room name) once the
 *   page has joined.
 * - Offline (the room runs in the page: Sandbox.sceneFile), Save downloads the world made into a
 *   file in the page, and Open checks a file the same way and opens it in the page's room; share
 *   links need a server to keep the scene, and the Save button and its notice say so.
 */
import { parseScene, SCENE_LIMITS } from '../games/index.ts'
import type { Sandbox } from './modes/index.ts'

const $ = <T extends HTMLElement = HTMLElement>(id: string): T => document.getElementById(id) as T

/** The page's side of saving, opening and sharing scene files. */
export class SceneFiles {
  /** The saveScene command waiting for its answer, and the scene to open once joined. */
  private pendingSave = 0
  private openOnJoin: string | null
  /** The last share link made (for the tests and the page). */
  lastShareLink = ''

  constructor(
    private readonly sandbox: Sandbox,
    private readonly httpBase: string,
    private readonly room: string,
    private readonly notify: (text: string) => void,
    shared: string | null,
  ) {
    this.openOnJoin = shared
    const online = typeof sandbox.roomCommand === 'function'
    const inPage = !online && typeof sandbox.sceneFile === 'function'
    for (const id of ['save-scene', 'open-scene']) $(id).hidden = !online && !inPage
    if (!online && !inPage) return
    if (inPage) {
      $('save-scene').title = 'Save the world as a scene file (share links need the sandbox online)'
      $('open-scene').title = 'Open a scene file here (or drop one on the page)'
    }
    $('save-scene').addEventListener('click', () => this.save())
    $('open-scene').addEventListener('click', () => $<HTMLInputElement>('scene-file').click())
    $<HTMLInputElement>('scene-file').addEventListener('change', (e) => {
      const input = e.target as HTMLInputElement
      const file = input.files?.[0]
      input.value = ''
      if (file) void this.open(file)
    })
    window.addEventListener('dragover', (e) => {
      if (e.dataTransfer?.types.includes('Files')) e.preventDefault()
    })
    window.addEventListener('drop', (e) => {
      const file = e.dataTransfer?.files?.[0]
      if (!file) return
      e.preventDefault()
      void this.open(file)
    })
  }

  /** Once a frame: open a shared scene after joining, and finish a save the server answered. */
  update(): void {
    if (this.openOnJoin !== null && this.sandbox.status().state === 'connected') {
      const seq = this.sandbox.roomCommand?.('openScene', { id: this.openOnJoin })
      if (seq !== null && seq !== undefined) this.openOnJoin = null
    }
    if (this.pendingSave !== 0) {
      const id = this.sandbox.savedScenes?.().get(this.pendingSave)
      if (id !== undefined) {
        this.pendingSave = 0
        void this.download(id)
      }
    }
  }

  /** Ask the room to save its world; update() downloads it when the server answers. Offline: download it now. */
  save(): void {
    const text = this.sandbox.roomCommand ? undefined : this.sandbox.sceneFile?.(this.room)
    if (text !== undefined) {
      const name = this.offer(new Blob([text], { type: 'application/json' }))
      this.notify(`Saved as ${name}. Share links need the sandbox online: a server keeps shared scenes.`)
      return
    }
    const seq = this.sandbox.roomCommand?.('saveScene', {}) ?? null
    if (seq === null) this.notify('Saving needs a connection to the server.')
    else this.pendingSave = seq
  }

  /** Check a scene file here, keep it on the server, and open it in this room. */
  async open(file: File): Promise<void> {
    if (file.size > SCENE_LIMITS.bytes)
      return this.notify(`${file.name} is ${file.size} bytes; a scene file is at most ${SCENE_LIMITS.bytes}.`)
    const text = await file.text()
    const parsed = parseScene(text)
    if (!parsed.ok) return this.notify(`${file.name} is not a scene file Concord can open: ${parsed.error}`)
    if (!this.sandbox.roomCommand && this.sandbox.openSceneFile) {
      const refused = this.sandbox.openSceneFile(parsed.scene, file.name)
      if (refused !== null) this.notify(refused)
      return
    }
    const res = await fetch(this.url('/scenes'), { method: 'POST', body: text })
    const body = await res.text()
    if (res.status !== 201) return this.notify(`The server did not keep ${file.name}: ${body.trim()}`)
    const { id } = JSON.parse(body) as { id: string }
    if (this.sandbox.roomCommand?.('openScene', { id }) === null) this.openOnJoin = id
  }

  /** Download a saved scene and offer its share link. */
  private async download(id: string): Promise<void> {
    const res = await fetch(this.url(`/scenes/${id}`))
    if (!res.ok) return this.notify(`The saved scene could not be fetched: ${(await res.text()).trim()}`)
    const name = this.offer(await res.blob())
    const key = new URLSearchParams(location.search).get('key')
    this.lastShareLink = `${this.httpBase}/?scene=${id}${key ? `&key=${encodeURIComponent(key)}` : ''}`
    let copied = ''
    try {
      await navigator.clipboard.writeText(this.lastShareLink)
      copied = ' (copied)'
    } catch {
      copied = ''
    }
    this.notify(`Saved as ${name}. Share link${copied}: ${this.lastShareLink}`)
  }

  /** Hand a scene file to the browser as a download named after the room; its file name. */
  private offer(blob: Blob): string {
    const a = document.createElement('a')
    a.href = URL.createObjectURL(blob)
    a.download = `${this.room}.json`
    document.body.append(a)
    a.click()
    a.remove()
    setTimeout(() => URL.revokeObjectURL(a.href), 10_000)
    return a.download
  }

  /** A server URL for `path`, with the page's access key when it has one. */
  private url(path: string): string {
    const key = new URLSearchParams(location.search).get('key')
    return `${this.httpBase}${path}${key ? `?key=${encodeURIComponent(key)}` : ''}`
  }
}
