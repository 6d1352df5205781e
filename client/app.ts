/*
 * The page: one animation-frame loop (the only wall-clock read besides the server's tick clock)
 * that advances the sandbox, computes the lab, and draws; and the DOM around the canvas: toolbar,
 * HUD, lab panel, status banner, help and lobby. Everything acts through the Sandbox interface,
 * so the page does not know whether the physics runs here or on the server.
 */
import { DEFAULT_SCENE, SCENES } from '../engine/index.ts'
import { type GameClient, keyCommand, MAX_HUD_ITEMS } from '../games/index.ts'
import { TICK_RATE } from '../shared/index.ts'
import {
  Camera,
  computeFreeBody,
  type DebugLayers,
  describeFreeBody,
  FpsMeter,
  type FreeBody,
  hudText,
  LabPlot,
  Renderer,
} from './draw/index.ts'
import {
  bodyRadius,
  driveSpeed,
  EditPanel,
  helpIntro,
  helpRows,
  JointPanel,
  pickBody,
  type ShortcutAction,
  SpawnPanel,
  shortcutFor,
  TOOL_COMMANDS,
  TOOLS,
  ToolController,
  type ToolName,
} from './input/index.ts'
import { cleanRoomName, offlineLink, replaysLink, roomLink, showLobby } from './lobby.ts'
import { findClientGameClient, type Sandbox, type ViewBody } from './modes/index.ts'
import { PlayerList } from './player-list.ts'
import { SceneFiles } from './scene-files.ts'

/** Shortest time between two changes of the hovered body whose contacts are drawn online (ms). */
const HOVER_MS = 150
/** How long after a scene is framed a newly seen player's cursor frames it again (ms). */
const REFIT_MS = 3000
/** On a touch screen a dropped shape is framed at least this wide (CSS px): a fingertip's size. */
const TOUCH_SPAWN_PX = 40
/** The spawn tools' shape at size 1x (m): a 1 m circle, box or polygon. */
const SPAWN_SHAPE_M = 1
/** How long a notice stays (ms), and how long at least before the next one replaces it. */
const TOAST_MS = 4000
const TOAST_MIN_MS = 1500

const $ = <T extends HTMLElement = HTMLElement>(id: string): T => document.getElementById(id) as T

/** The running page. */
/** Whether a notice is the room's refusal of an undo (redo) for a body or joint that is gone. */
function isStaleRefusal(notice: string, kind: 'undo' | 'redo'): boolean {
  return (
    notice.startsWith(`cannot ${kind} `) &&
    /: (body|joint) \d+ (was deleted|was removed|no longer exists)/.test(notice)
  )
}

/** How the page names a slow-motion factor. */
const SLOW_LABEL: Record<number, string> = { 1: '1×', 2: '1/2×', 4: '1/4×' }
/** The joint tools, behind the toolbar's Joints button. */
const JOINT_TOOLS: readonly ToolName[] = ['weld', 'hinge', 'spring', 'slider', 'wheel']
/** The toolbar's room controls and the command each sends (the game must list it: rules). */
const CONTROL_COMMANDS = {
  scene: 'scene',
  pause: 'pause',
  step: 'step',
  reset: 'reset',
  gravity: 'gravity',
  slow: 'slow',
  lock: 'lock',
} as const

export class App {
  readonly camera = new Camera()
  readonly renderer: Renderer
  readonly tools: ToolController
  /** Size and material sliders for the spawn tools. */
  readonly spawnPanel: SpawnPanel
  /** Motor, limit, spring and breaking force sliders for the joint tools. */
  readonly jointPanel: JointPanel
  /** The Edit tool's panel: the selection's material, colour, layer, static state and scale. */
  readonly editPanel: EditPanel
  /** What the Edit panel showed last frame (its layout changes with it). */
  private editPanelKey = ''
  /** The joint tool the toolbar's Joints button picks: the last one used. */
  private jointTool: ToolName = 'weld'
  readonly layers: DebugLayers = { contacts: false, joints: false, aabbs: false, ids: false }
  readonly fps = new FpsMeter()
  /** Latest free-body diagram (null when nothing is selected). */
  freeBody: FreeBody | null = null
  /** The selected body's speed and kinetic energy over the last seconds. */
  readonly labPlot = new LabPlot(TICK_RATE)
  private lastHud = 0
  /** The room's game's bound keys held now (lower case), and what the game panel shows. */
  private readonly gameKeysHeld = new Set<string>()
  private gamePanelKey = ''
  /** The body inspected for the contacts layer while nothing is selected, and when it was chosen. */
  private hover = { body: 0, at: Number.NEGATIVE_INFINITY }
  private fittedScene = ''
  /** The camera as fit() left it and when (performance.now() ms), and how many cursors it framed. */
  private fittedCamera: { x: number; y: number; scale: number; at: number } | null = null
  private fittedPeople = 0
  private lastToastCount = 0
  private toastTimer: ReturnType<typeof setTimeout> | undefined
  /** Notices waiting for the one shown to have been read, and when that one appeared (ms). */
  private readonly toastQueue: string[] = []
  private toastShownAt = Number.NEGATIVE_INFINITY
  private frameHandle = 0

  /** Save, open and share scene files (scene-files.ts). */
  readonly sceneFiles: SceneFiles
  readonly playerList: PlayerList

  constructor(
    readonly sandbox: Sandbox,
    private readonly httpBase: string,
    private readonly room: string,
    /** A shared scene's id (`?scene=ID`) to open in this room once joined, or null. */
    sharedScene: string | null = null,
  ) {
    const canvas = $<HTMLCanvasElement>('view')
    this.renderer = new Renderer(canvas, this.camera)
    this.spawnPanel = new SpawnPanel($('spawn-panel'))
    this.jointPanel = new JointPanel($('joint-panel'))
    this.tools = new ToolController(
      canvas,
      this.camera,
      () => this.sandbox,
      this.spawnPanel.settings,
      this.jointPanel.settings,
    )
    this.tools.onNotice = (text) => this.toast(text)
    this.tools.allows = (kind) => this.allows(kind)
    this.tools.gameClient = () => this.gameClient()
    this.editPanel = new EditPanel($('edit-panel'), this.tools.edit)
    this.renderer.resize()
    window.addEventListener('resize', () => {
      this.renderer.resize()
      this.placePanels()
    })
    window.addEventListener('blur', () => {
      this.tools.cancel()
      this.releaseGameKeys()
    })
    window.addEventListener('keydown', (e) => this.key(e))
    window.addEventListener('keyup', (e) => {
      if (!this.gameKey(e, false)) this.drive(e, false)
    })
    this.wireToolbar()
    this.sceneFiles = new SceneFiles(sandbox, httpBase, room, (text) => this.notify(text), sharedScene)
    this.playerList = new PlayerList(sandbox, (text) => this.notify(text))
    $('help-rows').innerHTML = helpRows(touchLayout())
    $('help-intro').textContent = helpIntro(touchLayout())
    this.setTool('grab')
    this.placePanels()
    this.frameHandle = requestAnimationFrame((t) => this.frame(t))
  }

  private wireToolbar(): void {
    for (const b of document.querySelectorAll<HTMLButtonElement>('[data-tool]')) {
      b.addEventListener('click', () => this.act(`tool:${b.dataset.tool}` as ShortcutAction))
    }
    $('joints').addEventListener('click', () => this.setTool(this.jointTool))
    const scene = $<HTMLSelectElement>('scene')
    scene.addEventListener('change', () => {
      this.sandbox.send({ k: 'scene', name: scene.value })
      scene.blur()
    })
    // Open (focused), the picker describes each scene; closed, it names the scene only.
    scene.addEventListener('focus', () => this.labelScenes(true))
    scene.addEventListener('mousedown', () => this.labelScenes(true))
    scene.addEventListener('blur', () => this.labelScenes(false))
    const click = (id: string, action: ShortcutAction): void =>
      $(id).addEventListener('click', () => this.act(action))
    click('pause', 'pause')
    click('step', 'step')
    click('reset', 'reset')
    click('gravity', 'gravity')
    click('slow', 'slow')
    click('lock', 'lock')
    click('undo', 'undo')
    click('redo', 'redo')
    click('help-button', 'help')
    click('help-close', 'help')
    click('rooms', 'lobby')
    click('lobby-close', 'lobby')
    click('fit', 'fit')
    click('static', 'static')
    // Debug opens the layer buttons; each layer is its own toggle (touch-sized, showing on/off).
    $('layers').addEventListener('click', () => {
      $('layers-panel').hidden = !$('layers-panel').hidden
      this.syncToggles()
      this.placePanels()
    })
    for (const b of document.querySelectorAll<HTMLButtonElement>('[data-layer]')) {
      b.addEventListener('click', () => this.act(`layer:${b.dataset.layer}` as ShortcutAction))
    }
    // Opened from disk or from the static build there is no server: no rooms, no going online.
    $('mode').hidden = $('rooms').hidden = !hasServer()
    $('mode').textContent = this.sandbox.mode === 'online' ? 'Offline' : 'Online'
    $('mode').addEventListener('click', () => {
      location.href =
        this.sandbox.mode === 'online'
          ? offlineLink(this.room, this.sandbox.scene() || DEFAULT_SCENE)
          : roomLink(this.room)
    })
    $('go-offline').addEventListener('click', () => {
      location.href = offlineLink(this.room, this.sandbox.scene() || DEFAULT_SCENE)
    })
    $('retry').addEventListener('click', () => this.sandbox.retry())
    $('create-room').addEventListener('click', () => {
      const name = cleanRoomName($<HTMLInputElement>('new-room').value)
      if (name) location.href = roomLink(name)
      else $('lobby-list').textContent = 'Room names use letters, digits, - and _ (at most 32).'
    })
  }

  /** Show on every toggle button whether it is on (aria-pressed, drawn as an underline). */
  syncToggles(): void {
    for (const b of document.querySelectorAll<HTMLButtonElement>('[data-layer]')) {
      b.setAttribute('aria-pressed', String(this.layers[b.dataset.layer as keyof DebugLayers]))
    }
    $('layers').setAttribute('aria-pressed', String(!$('layers-panel').hidden))
    const g = this.sandbox.gravity()
    $('gravity').setAttribute('aria-pressed', String(g.x !== 0 || g.y !== 0))
    $('pause').setAttribute('aria-pressed', String(this.sandbox.paused()))
  }

  /**
   * Tell the CSS where the toolbar ends (--bar-bottom) and where the panels under it end
   * (--panels-bottom: the Debug layer row when open): on a phone the toolbar wraps onto several
   * rows and the HUD, the layer row and notices are placed below it. --bottom-inset is the height
   * of a bar along the bottom (the replay controls): the HUD sits above it.
   */
  placePanels(): void {
    const root = document.documentElement.style
    const bar = $('toolbar').getBoundingClientRect().bottom
    root.setProperty('--bar-bottom', `${Math.round(bar)}px`)
    // Stacked under the toolbar at the left: the Debug layer row, then the spawn sliders.
    let below = bar
    for (const [id, property] of [
      ['layers-panel', '--layers-top'],
      ['spawn-panel', '--spawn-top'],
      ['joint-panel', '--joint-top'],
      ['edit-panel', '--edit-top'],
    ]) {
      root.setProperty(property, `${Math.round(below)}px`)
      const panel = $(id)
      if (!panel.hidden) below = panel.getBoundingClientRect().bottom
    }
    root.setProperty('--panels-bottom', `${Math.round(below)}px`)
    root.setProperty('--bottom-inset', `${Math.round(this.bottomInset())}px`)
  }

  /** CSS px at the bottom of the view that a bar covers (the replay controls), else 0. */
  private bottomInset(): number {
    const bar = document.getElementById('replay-panel')
    if (!bar || bar.hidden) return 0
    const top = bar.getBoundingClientRect().top
    return top > 0 ? Math.max(0, window.innerHeight - top) : 0
  }

  /**
   * Undo or redo this player's last action (the sandbox's game commands). After a notice that
   * refused one for a body or joint that is gone, the next press skips it (`{skip: true}`: the
   * gone action is dropped and the one before it undone).
   */
  private undoRedo(kind: 'undo' | 'redo'): void {
    const s = this.sandbox
    if (!this.undoable()) {
      this.toast('Undo and redo need a room that runs the sandbox game (online or offline)')
      return
    }
    s.sendGame(kind, isStaleRefusal(s.notices().latest ?? '', kind) ? { skip: true } : {})
  }

  /**
   * Whether the room's game lists a command kind, built-in (rules.builtins) or its own
   * (rules.commands). In replays and before the welcome there are no rules: everything.
   */
  private allows(kind: string): boolean {
    const rules = this.sandbox.rules()
    return rules === null || rules.builtins.includes(kind) || rules.commands.includes(kind)
  }

  /** A tool the room's game offers (its command is listed; the Lab always). */
  private offers(tool: ToolName): boolean {
    const kind = TOOL_COMMANDS[tool]
    return kind === null || this.allows(kind)
  }

  /** Whether this page's room offers undo and redo (the sandbox online, in lockstep or offline). */
  private undoable(): boolean {
    return this.sandbox.rules()?.commands?.includes('undo') ?? false
  }

  /** The Draw tool's next form, named on its button's title and in a notice. */
  private cycleDrawForm(): void {
    const form = this.tools.cycleDrawForm()
    const name = { outline: 'outline', rect: 'rectangle', circle: 'circle', capsule: 'capsule' }[form]
    const how = form === 'outline' ? 'drag freehand or click corners' : 'drag'
    const button = document.querySelector<HTMLButtonElement>('[data-tool="draw"]')
    if (button) button.dataset.title = `Draw: ${name} (W; again: the next form)`
    this.toast(`Draw: ${name} (${how})`)
  }

  /** Show the player a notice (queued behind the one shown). */
  toast(text: string): void {
    this.toastQueue.push(text)
    this.showNextToast()
  }

  /** Switch the active tool. */
  setTool(tool: ToolName): void {
    this.tools.cancel()
    this.tools.tool = tool
    if (tool !== 'inspect') this.tools.selected = 0
    for (const b of document.querySelectorAll<HTMLButtonElement>('[data-tool]')) {
      b.classList.toggle('active', b.dataset.tool === tool)
    }
    // A replay spawns nothing: its keys may pick a tool, but the spawn sliders stay closed.
    const spawns = tool === 'circle' || tool === 'box' || tool === 'polygon' || tool === 'draw'
    this.spawnPanel.show(spawns && this.sandbox.mode !== 'replay')
    const joints = JOINT_TOOLS.includes(tool)
    this.jointPanel.show(joints && this.sandbox.mode !== 'replay')
    if (joints) this.jointTool = tool
    if (tool !== 'edit') this.tools.edit.clear()
    this.editPanel.show(tool === 'edit' && this.sandbox.mode !== 'replay')
    $('joints').classList.toggle('active', joints)
    this.placePanels()
  }

  private key(e: KeyboardEvent): void {
    if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return
    if (this.gameKey(e, true)) return
    if (this.drive(e, true)) return
    const action = shortcutFor(e)
    if (!action) return
    e.preventDefault()
    this.act(action)
  }

  /**
   * The room's game's client module (docs/games.md, "Client modules"), or undefined: offline, in
   * replays, and in rooms of a game without one.
   */
  private gameClient(): GameClient | undefined {
    const s = this.sandbox
    if (!s.gameState) return undefined
    return findClientGameClient(s.rules()?.game ?? '')
  }

  /**
   * A key the room's game binds (its client module's keys win over the page's shortcuts and drive
   * keys): sends the command the binding returns for the key going down or up. Returns whether the
   * game binds the key.
   */
  private gameKey(e: KeyboardEvent, down: boolean): boolean {
    if (e.ctrlKey || e.altKey || e.metaKey) return false
    if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return false
    const client = this.gameClient()
    const key = e.key.toLowerCase()
    const binding = client?.keys[key]
    if (!client || !binding) return false
    e.preventDefault()
    if (down && (e.repeat || this.gameKeysHeld.has(key))) return true
    if (!down && !this.gameKeysHeld.has(key)) return true
    if (down) this.gameKeysHeld.add(key)
    else this.gameKeysHeld.delete(key)
    this.sendGameKey(client, key, down)
    return true
  }

  private sendGameKey(client: GameClient, key: string, down: boolean): void {
    const s = this.sandbox
    const cmd = keyCommand(client.keys[key], down, {
      state: s.gameState?.() ?? null,
      me: s.playerId(),
      held: this.gameKeysHeld,
    })
    if (cmd) s.sendGame(cmd.kind, cmd.args)
  }

  /** The page lost the keyboard: every game key held counts as released (a disc stops running). */
  private releaseGameKeys(): void {
    const client = this.gameClient()
    const held = [...this.gameKeysHeld]
    this.gameKeysHeld.clear()
    if (client) for (const key of held) if (client.keys[key]) this.sendGameKey(client, key, false)
  }

  /** The game panel: the room's game's HUD items, hidden without a client module or items. */
  private refreshGamePanel(): void {
    const panel = $('game-panel')
    const client = this.gameClient()
    const s = this.sandbox
    const items = client?.hud?.(s.gameState?.() ?? null, s.playerId()).slice(0, MAX_HUD_ITEMS) ?? []
    const key = items.map((i) => `${i.label}\u0000${i.value}`).join('\u0001')
    if (key === this.gamePanelKey) return
    this.gamePanelKey = key
    panel.hidden = items.length === 0
    panel.replaceChildren(
      ...items.map((item) => {
        const div = document.createElement('span')
        div.className = 'item'
        div.dataset.label = item.label
        const value = document.createElement('b')
        value.textContent = String(item.value)
        div.append(String(item.label), value)
        return div
      }),
    )
  }

  /** The room's game's extra drawing, after the world (screen coordinates). */
  private drawGame(): void {
    const client = this.gameClient()
    if (!client?.draw) return
    const s = this.sandbox
    const ctx = this.renderer.ctx
    ctx.save()
    try {
      client.draw(ctx, (x, y) => this.camera.toScreen(x, y), s.gameState?.() ?? null, s.playerId())
    } finally {
      ctx.restore()
    }
  }

  /**
   * The arrow keys drive the motors of the joints this player made (the room refuses others'):
   * pressed, each of your wheels, hinges or sliders with a motor runs at DRIVE_SPEED; released, it
   * stops. Returns whether the key was a drive key.
   */
  private drive(e: KeyboardEvent, down: boolean): boolean {
    if (!e.key.startsWith('Arrow') || e.ctrlKey || e.altKey || e.metaKey) return false
    if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return false
    e.preventDefault()
    if (e.repeat) return true
    const me = this.sandbox.playerId()
    if (me === 0) return true
    for (const j of this.sandbox.joints()) {
      if (j.spec.owner !== me) continue
      const speed = driveSpeed(j.spec, e.key)
      if (speed === undefined) continue
      this.sandbox.sendGame('jointMotor', { joint: j.id, speed: down ? speed : 0 })
    }
    return true
  }

  /** Perform one toolbar or keyboard action. */
  act(action: ShortcutAction): void {
    const s = this.sandbox
    if (action.startsWith('tool:')) {
      const tool = action.slice(5) as ToolName
      if (!this.offers(tool)) {
        this.toast(`This room's game (${s.rules()?.game}) has no ${tool} tool`)
        return
      }
      // Draw again: its next form (outline, rectangle, circle, capsule).
      if (tool === 'draw' && this.tools.tool === 'draw') this.cycleDrawForm()
      else this.setTool(tool)
      return
    }
    if (action.startsWith('layer:')) {
      const layer = action.slice(6) as keyof DebugLayers
      this.layers[layer] = !this.layers[layer]
      this.syncToggles()
      return
    }
    if (
      Object.hasOwn(CONTROL_COMMANDS, action) &&
      !this.allows(CONTROL_COMMANDS[action as keyof typeof CONTROL_COMMANDS])
    ) {
      this.toast(`This room's game (${s.rules()?.game}) has no ${action} control`)
      return
    }
    switch (action) {
      case 'pause':
        s.send({ k: 'pause', paused: !s.paused() })
        break
      case 'step':
        s.send({ k: 'step' })
        break
      case 'reset':
        s.send({ k: 'reset' })
        break
      case 'gravity': {
        const g = s.gravity()
        s.send(g.y !== 0 || g.x !== 0 ? { k: 'gravity', x: 0, y: 0 } : { k: 'gravity', x: 0, y: -10 })
        break
      }
      case 'slow': {
        const slow = s.roomControl?.().slow ?? 1
        s.sendGame?.('slow', { every: slow === 1 ? 2 : slow === 2 ? 4 : 1 })
        break
      }
      case 'lock':
        s.sendGame?.('lock', { locked: !(s.roomControl?.().locked ?? false) })
        break
      case 'undo':
      case 'redo':
        this.undoRedo(action)
        break
      case 'fit':
        this.fit()
        break
      case 'static':
        this.tools.makeStatic = !this.tools.makeStatic
        $('static').setAttribute('aria-pressed', String(this.tools.makeStatic))
        $('static').classList.toggle('active', this.tools.makeStatic)
        break
      case 'finish':
        this.tools.finishPending()
        break
      case 'delete-selection':
        if (this.tools.tool === 'edit') this.tools.edit.deleteSelection()
        break
      case 'help':
        $('help').hidden = !$('help').hidden
        // Built on opening: the room's game (and so its keys) is known once the page joined.
        if (!$('help').hidden) $('help-rows').innerHTML = helpRows(touchLayout(), this.gameClient())
        break
      case 'lobby':
        if (!hasServer()) break
        $('lobby').hidden = !$('lobby').hidden
        $('replays-link').setAttribute('href', replaysLink())
        if (!$('lobby').hidden) void showLobby($('lobby-list'), this.httpBase, this.room)
        break
      case 'escape':
        $('help').hidden = true
        $('lobby').hidden = true
        this.tools.cancel()
        this.tools.selected = 0
        this.tools.edit.clear()
        return
    }
  }

  /**
   * Frame the scene in the view: its movable bodies, its joints' anchors (a cradle's rods hang
   * from above its balls), the ground line and the other players' cursors and held bodies, but not
   * strays: bodies below the ground or much farther from the scene's middle than the rest (flung
   * away) are left out unless a player holds them.
   */
  fit(): void {
    const points: Array<{ x: number; y: number; r: number }> = []
    // Other players, wherever they are: their cursors and what they hold are never strays.
    const people: Array<{ x: number; y: number; r: number }> = []
    const cursors = this.sandbox.cursors()
    const held = new Set(cursors.map((c) => c.body))
    for (const c of cursors) people.push({ x: c.x, y: c.y, r: 0.5 })
    for (const b of this.sandbox.bodies()) {
      const r = bodyRadius(b)
      if (b.kind === 0 && r > 50) continue // the ground: frame what stands on it instead
      if (held.has(b.id)) people.push({ x: b.x, y: b.y, r })
      else if (b.kind !== 0 && b.y + r < -1)
        continue // fallen off the ground
      else points.push({ x: b.x, y: b.y, r })
    }
    for (const j of this.sandbox.joints())
      points.push({ x: j.ax, y: j.ay, r: 0.2 }, { x: j.bx, y: j.by, r: 0.2 })
    const kept = [...withoutStrays(points), ...people]
    this.fittedPeople = cursors.length
    let [minX, minY, maxX, maxY] = [Infinity, 0, -Infinity, 4]
    for (const p of kept) {
      minX = Math.min(minX, p.x - p.r)
      maxX = Math.max(maxX, p.x + p.r)
      minY = Math.min(minY, p.y - p.r)
      maxY = Math.max(maxY, p.y + p.r)
    }
    if (!Number.isFinite(minX)) [minX, maxX] = [-10, 10]
    const toolbar = $('toolbar').getBoundingClientRect()
    const bottom = this.bottomInset()
    this.camera.fit(minX, minY, maxX, maxY, toolbar.bottom, bottom)
    const fingerScale = TOUCH_SPAWN_PX / (SPAWN_SHAPE_M * this.spawnPanel.settings.size)
    if (touchLayout() && kept.length === 0 && this.camera.scale < fingerScale) {
      // Nothing to frame but the ground (the empty scene): a finger needs bigger targets than a
      // 20 m stretch of ground at once, so zoom until a dropped shape is TOUCH_SPAWN_PX wide, keep
      // the middle, and keep the ground a little above the bottom edge. A scene with bodies is
      // framed whole (pinch to zoom in).
      const c = this.camera
      c.scale = fingerScale
      c.y = Math.max(minY - 1, -1) + (c.height / 2 - bottom) / c.scale
    }
    this.fittedCamera = {
      x: this.camera.x,
      y: this.camera.y,
      scale: this.camera.scale,
      at: performance.now(),
    }
  }

  /**
   * A late joiner's first frames: other players' cursors arrive after the bodies that the scene
   * was framed on. While the camera is as fit() left it (nobody panned or zoomed) and for a few
   * seconds after, a newly seen cursor frames the scene again, with the cursors and what they hold.
   */
  private refitForPeople(now: number): void {
    const fitted = this.fittedCamera
    const c = this.camera
    if (!fitted || now - fitted.at > REFIT_MS) return
    if (c.x !== fitted.x || c.y !== fitted.y || c.scale !== fitted.scale) return
    const cursors = this.sandbox.cursors()
    if (cursors.length <= this.fittedPeople) return
    this.fit()
  }

  private frame(now: number): void {
    this.frameHandle = requestAnimationFrame((t) => this.frame(t))
    this.fps.frame(now)
    const s = this.sandbox
    s.update(now)
    this.sceneFiles.update()
    this.playerList.update()
    const scene = s.scene()
    if (scene && scene !== this.fittedScene && s.bodies().length > 0) {
      this.fittedScene = scene
      this.fit()
      this.syncScenePicker()
    } else this.refitForPeople(now)
    const selected = this.selectedBody()
    s.inspect(selected?.id ?? this.hoverInspect(now))
    const lab = selected ? s.lab(selected.id) : null
    this.freeBody = selected && lab ? computeFreeBody(selected.id, lab) : null
    if (selected && this.freeBody) {
      this.labPlot.add(selected.id, s.stats().tick, this.freeBody)
      this.labPlot.draw($<HTMLCanvasElement>('lab-plot'))
    } else if (!selected) this.labPlot.clear()
    this.renderer.draw({
      bodies: s.bodies(),
      joints: s.joints(),
      cursors: s.cursors(),
      contacts: s.contacts(),
      layers: this.layers,
      overlay: this.tools.overlay(s.color()),
      selected,
      freeBody: this.freeBody,
    })
    this.drawGame()
    if (this.tools.tool === 'edit') {
      const wasShown = this.editPanelKey
      this.editPanel.refresh(this.tools.edit.bodies(), this.tools.edit.selectedJoint())
      this.editPanelKey = this.editPanel.key
      if (wasShown !== this.editPanelKey) this.placePanels()
    }
    if (now - this.lastHud > 250) {
      this.lastHud = now
      this.refreshPanels(selected)
    }
  }

  /**
   * With the contacts layer on and nothing selected, the body under the pointer is inspected, so
   * an online room streams its contacts to draw (a room sends one body's contacts to a player: all
   * of them would not fit the bandwidth budget). The choice changes at most every HOVER_MS so a
   * sweep over a pile does not flood the room with inspect commands.
   */
  private hoverInspect(now: number): number {
    if (!this.layers.contacts || this.sandbox.mode !== 'online') return 0
    if (now - this.hover.at < HOVER_MS) return this.hover.body
    const p = this.tools.pointer
    const body = p ? pickBody(this.sandbox.bodies(), p, (b) => b.kind === 2) : null
    if (body && body.id !== this.hover.body) this.hover = { body: body.id, at: now }
    return this.hover.body
  }

  private selectedBody(): ViewBody | null {
    const id = this.tools.selected
    if (!id) return null
    const body = this.sandbox.bodies().find((b) => b.id === id) ?? null
    if (!body) this.tools.selected = 0
    return body
  }

  /**
   * Fill the scene picker: each option names its scene and, while the picker is open, says what
   * the scene holds (SCENES' descriptions); closed, it shows the name alone so the toolbar keeps
   * its width, with the description as its tooltip.
   */
  private syncScenePicker(): void {
    const select = $<HTMLSelectElement>('scene')
    const names = this.sandbox.rules()?.scenes ?? Object.keys(SCENES)
    if (select.options.length !== names.length) {
      select.replaceChildren(
        ...names.map((n) => {
          const option = document.createElement('option')
          option.value = n
          option.dataset.description = sceneDescription(n)
          return option
        }),
      )
      this.labelScenes(false)
    }
    select.value = this.sandbox.scene()
    select.title = `Scene: ${sceneDescription(select.value)}`
  }

  /** Scene options as "name: description" (picker open) or "name" (closed). */
  private labelScenes(open: boolean): void {
    for (const option of $<HTMLSelectElement>('scene').options) {
      const description = option.dataset.description
      option.textContent = open && description ? `${option.value}: ${description}` : option.value
    }
  }

  private refreshPanels(selected: ViewBody | null): void {
    const s = this.sandbox
    // A game room that loads no scenes holds its game's world: name the game, not the default scene.
    const rules = s.rules()
    const shown = rules && rules.scenes.length === 0 ? `game ${rules.game}` : s.scene()
    $('hud').textContent = hudText(s.stats(), this.fps.value, s.mode, shown)
    this.refreshGamePanel()
    const room = s.roomControl?.() ?? null
    const lockedOut = room?.locked && room.self !== room.creator
    const controls = (s.rules()?.controls ?? true) && !lockedOut
    $('undo').hidden = $('redo').hidden = !this.undoable()
    for (const id of ['scene', 'pause', 'step', 'reset', 'gravity', 'slow', 'lock'] as const) {
      const control = $(id) as HTMLButtonElement
      control.hidden = !this.allows(CONTROL_COMMANDS[id])
      // The scene picker's own title names the current scene (syncScenePicker): read it afresh.
      if (id === 'scene') control.dataset.title = `Scene: ${sceneDescription(s.scene())}`
      else control.dataset.title ??= control.title
      control.disabled = !controls
      control.title = controls
        ? control.dataset.title
        : lockedOut
          ? `${control.dataset.title}: the room's creator locked the controls`
          : `${control.dataset.title}: not open to you in this room (with an admin key, add &key=KEY to the address)`
    }
    $('pause').textContent = s.paused() ? 'Play' : 'Pause'
    const slow = room?.slow ?? 1
    $('slow').hidden ||= room === null
    $('slow').textContent = SLOW_LABEL[slow] ?? `1/${slow}×`
    $('slow').setAttribute('aria-pressed', String(slow !== 1))
    // Only the room's creator can lock; offline there is nobody to lock out.
    $('lock').hidden ||=
      room === null || room.creator === 0 || room.self !== room.creator || s.mode === 'offline'
    $('lock').setAttribute('aria-pressed', String(room?.locked ?? false))
    $('lock').textContent = room?.locked ? '🔒' : '🔓'
    // On the view itself, not only on the button (the replay page has its own Play button).
    const banner: string[] = []
    if (s.paused()) banner.push(controls ? '❚❚ Paused: Space or Play resumes' : '❚❚ Paused by the room')
    if (slow !== 1) banner.push(`◷ Slow motion ${SLOW_LABEL[slow] ?? slow}`)
    if (room?.locked)
      banner.push(
        room.self === room.creator
          ? '🔒 You locked the controls'
          : "🔒 Controls locked by the room's creator",
      )
    $('paused').hidden = banner.length === 0 || s.mode === 'replay'
    $('paused').textContent = banner.join(' · ')
    this.syncToggles()
    this.placePanels()
    if ($<HTMLSelectElement>('scene').value !== s.scene()) this.syncScenePicker()
    $('lab').hidden = !selected
    if (selected) {
      $('lab-text').textContent = this.freeBody
        ? describeFreeBody(selected.id, this.freeBody)
        : selected.kind === 2
          ? `body ${selected.id}\nwaiting for the server's contacts`
          : `body ${selected.id}\nnot a dynamic body: no free-body diagram`
    }
    const status = s.status()
    // Tools cannot act while the page is not in its room: say so on every tool button.
    const away = s.mode === 'online' && status.state !== 'connected'
    // A game room offers only the tools its game lists (the Lab always): the current one too.
    if (!this.offers(this.tools.tool)) this.setTool(TOOLS.find((t) => this.offers(t)) ?? 'inspect')
    $('joints').hidden = !JOINT_TOOLS.some((t) => this.offers(t))
    $('static').hidden = !this.allows('spawn')
    $('open-scene').hidden = !this.allows('scene')
    for (const b of document.querySelectorAll<HTMLButtonElement>('[data-tool]')) {
      b.hidden = !this.offers(b.dataset.tool as ToolName)
      b.dataset.title ??= b.title
      b.disabled = away
      const why = status.state === 'error' && !status.retrying ? 'not in the room' : 'offline, reconnecting'
      b.title = away ? `${b.dataset.title}: ${why}` : b.dataset.title
    }
    if (selected) this.keepInView(selected)
    $('banner').hidden = status.state !== 'error'
    if (status.state === 'error') {
      const wait =
        status.retryAt === undefined ? null : Math.max(0, (status.retryAt - performance.now()) / 1000)
      $('banner-text').textContent =
        wait === null ? status.message : `${status.message} in ${wait.toFixed(0)} s…`
      $('retry').hidden = !status.retrying
    }
    const notices = s.notices()
    if (notices.count !== this.lastToastCount) {
      // Every notice since the last refresh (up to the few a mode keeps), queued without repeats.
      const fresh = notices.count - this.lastToastCount
      this.lastToastCount = notices.count
      const lines = notices.recent ? notices.recent.slice(-fresh) : [notices.latest ?? '']
      for (const raw of lines) {
        const kind = raw.startsWith('cannot redo ') ? 'redo' : 'undo'
        const line = isStaleRefusal(raw, kind)
          ? `${raw} (press ${kind === 'undo' ? 'Undo' : 'Redo'} again to skip it)`
          : raw
        const last = this.toastQueue.at(-1) ?? (this.toastVisible ? $('toast').textContent : null)
        if (line !== last) this.toastQueue.push(line)
      }
    }
    this.showNextToast()
  }

  /** Show the player a notice of the page's own (queued like the sandbox's). */
  notify(text: string): void {
    this.toastQueue.push(text)
    this.showNextToast()
  }

  /**
   * One notice at a time, never a stack: the next waits until the shown one has been up
   * TOAST_MIN_MS; the last stays TOAST_MS.
   */
  private showNextToast(): void {
    const now = performance.now()
    if (this.toastQueue.length === 0 || (this.toastVisible && now - this.toastShownAt < TOAST_MIN_MS)) return
    $('toast').textContent = this.toastQueue.shift() ?? ''
    $('toast').hidden = false
    this.toastShownAt = now
    clearTimeout(this.toastTimer)
    this.toastTimer = setTimeout(() => ($('toast').hidden = true), TOAST_MS)
  }

  private get toastVisible(): boolean {
    return !$('toast').hidden
  }

  /** Pan so the toolbar and the lab panel do not cover the selected body (small screens). */
  private keepInView(body: ViewBody): void {
    const top = $('toolbar').getBoundingClientRect().bottom
    const lab = $('lab').getBoundingClientRect()
    const bottom = lab.height > 0 ? lab.top : this.camera.height
    const p = this.camera.toScreen(body.x, body.y)
    const r = bodyRadius(body) * this.camera.scale
    if (p.y - r >= top && p.y + r <= bottom) return
    if (bottom - top < 2 * r) return
    // Centre the body in the free band between them.
    const target = (top + bottom) / 2
    this.camera.y = body.y - (this.camera.height / 2 - target) / this.camera.scale
  }

  /** Stop the loop. */
  stop(): void {
    cancelAnimationFrame(this.frameHandle)
    this.sandbox.dispose()
  }
}

/** Whether the page is used by touch (a coarse pointer: a phone or tablet). */
export function touchLayout(): boolean {
  return typeof matchMedia === 'function' && matchMedia('(pointer: coarse)').matches
}

/**
 * Whether a game server served this page: not when it was opened from disk (file:) or comes from
 * the static build (scripts/build-static.mjs marks it with <meta name="concord-mode" content="offline">).
 */
export function hasServer(): boolean {
  const staticBuild = document.querySelector('meta[name="concord-mode"][content="offline"]') !== null
  return location.protocol !== 'file:' && !staticBuild
}

/** What a scene holds (SCENES' description), or '' for a scene this page does not know. */
function sceneDescription(name: string): string {
  return Object.hasOwn(SCENES, name) ? SCENES[name].description : ''
}

/** The tools in toolbar order (re-exported for tests and the README). */
export { TOOLS }

/**
 * Points without strays: those farther from the median point than 4 times the median distance
 * plus 10 m (a body flung far along the ground) are dropped.
 */
export function withoutStrays<T extends { x: number; y: number }>(points: T[]): T[] {
  if (points.length < 4) return points
  const median = (values: number[]): number => values.sort((a, b) => a - b)[Math.floor(values.length / 2)]
  const cx = median(points.map((p) => p.x))
  const cy = median(points.map((p) => p.y))
  const distance = (p: T): number => Math.hypot(p.x - cx, p.y - cy)
  const limit = 4 * median(points.map(distance)) + 10
  return points.filter((p) => distance(p) <= limit)
}
