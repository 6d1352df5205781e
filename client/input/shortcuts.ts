/*
 * Keyboard shortcuts: one table drives both the key handling and the help overlay, so the help
 * can never list a key that does nothing. The tools come in toolbar order, named as their buttons
 * are, with the digit keys 1-9 along the toolbar. In a room whose game has a client module, its
 * keys (which win over these) come first, and the shortcuts they take are left out.
 */
import type { GameClient } from '../../games/index.ts'

/** What a shortcut does; main.ts maps each action to code. */
export type ShortcutAction =
  | 'tool:grab'
  | 'tool:circle'
  | 'tool:box'
  | 'tool:polygon'
  | 'tool:delete'
  | 'tool:pin'
  | 'tool:rope'
  | 'tool:cut'
  | 'tool:inspect'
  | 'tool:draw'
  | 'tool:ground'
  | 'static'
  | 'finish'
  | 'tool:weld'
  | 'tool:hinge'
  | 'tool:spring'
  | 'tool:slider'
  | 'tool:wheel'
  | 'tool:explode'
  | 'tool:edit'
  | 'delete-selection'
  | 'slow'
  | 'lock'
  | 'undo'
  | 'redo'
  | 'pause'
  | 'step'
  | 'reset'
  | 'gravity'
  | 'fit'
  | 'layer:contacts'
  | 'layer:joints'
  | 'layer:aabbs'
  | 'layer:ids'
  | 'help'
  | 'lobby'
  | 'escape'

/** The shortcut table: keys (KeyboardEvent.key, lower case), action, description. */
export const SHORTCUTS: ReadonlyArray<{ keys: string[]; action: ShortcutAction; help: string }> = [
  { keys: ['g', '1'], action: 'tool:grab', help: 'Grab: drag a body, let go while moving to throw it' },
  { keys: ['c', '2'], action: 'tool:circle', help: 'Circle: click to drop one, drag to throw it' },
  { keys: ['b', '3'], action: 'tool:box', help: 'Box: click to drop one, drag to throw it' },
  {
    keys: ['p', '4'],
    action: 'tool:polygon',
    help: 'Polygon: click to drop one (3-8 sides, cycling; the next one is shown at the pointer)',
  },
  { keys: ['x', '5'], action: 'tool:delete', help: 'Delete: click a body' },
  {
    keys: ['n', '6'],
    action: 'tool:pin',
    help: 'Pin: click a body to pin it to what is under it (or the world)',
  },
  { keys: ['l', '7'], action: 'tool:rope', help: 'Rope: drag from one body (or space) to another' },
  { keys: ['u', '8'], action: 'tool:cut', help: 'Cut: click a pin, rope, rod or spring to remove it' },
  { keys: ['i', '9'], action: 'tool:inspect', help: 'Lab: click a body to see its free-body diagram' },
  {
    keys: ['w', '0'],
    action: 'tool:draw',
    help: 'Draw: drag a shape (or click corners); again: box, circle, capsule',
  },
  {
    keys: ['t'],
    action: 'tool:ground',
    help: 'Ground: drag a static line (or click points)',
  },
  {
    keys: ['/'],
    action: 'tool:explode',
    help: 'Explode: press to see the blast, release to push everything in it away',
  },
  {
    keys: [';'],
    action: 'tool:edit',
    help: 'Edit: click a body to change it (the panel) or drag it to move (Shift: turn); drag on empty space to select several',
  },
  { keys: ['delete', 'backspace'], action: 'delete-selection', help: 'Delete what the Edit tool selected' },
  { keys: ['m'], action: 'static', help: 'Static: what you draw or drop stays put (on / off)' },
  { keys: ['enter'], action: 'finish', help: 'Finish the outline or line you are clicking' },
  { keys: ['y'], action: 'tool:weld', help: 'Weld: click a body to glue it to what is under it' },
  {
    keys: ['e'],
    action: 'tool:hinge',
    help: 'Hinge: click a body to hinge it to what is under it (motor and limit: the panel); ←/→ drive yours',
  },
  { keys: ['q'], action: 'tool:spring', help: 'Spring: drag from one body (or space) to another' },
  {
    keys: ['z'],
    action: 'tool:slider',
    help: 'Slider: drag from a body the way it should slide; ↑/↓ drive yours',
  },
  {
    keys: [','],
    action: 'tool:wheel',
    help: 'Wheel: click a chassis to add a driven wheel; ←/→ drive yours',
  },
  {
    keys: ['ctrl+z'],
    action: 'undo',
    help: 'Undo your last spawn, drawing, delete, joint or cut (each player undoes their own)',
  },
  { keys: ['ctrl+shift+z', 'ctrl+y'], action: 'redo', help: 'Redo what you undid' },
  { keys: [' '], action: 'pause', help: 'Pause / resume' },
  { keys: ['s', '.'], action: 'step', help: 'Single step (while paused)' },
  { keys: ['r'], action: 'reset', help: 'Reset the scene' },
  { keys: ['v'], action: 'gravity', help: 'Gravity on / off' },
  { keys: ['-'], action: 'slow', help: 'Slow motion: full, 1/2, 1/4 speed (for everyone in the room)' },
  { keys: ['='], action: 'lock', help: "Lock the room controls to yourself (the room's creator only)" },
  { keys: ['f'], action: 'fit', help: 'Fit the scene in view' },
  { keys: ['k'], action: 'layer:contacts', help: 'Debug: contact points and normals' },
  { keys: ['j'], action: 'layer:joints', help: 'Debug: joint anchors' },
  { keys: ['a'], action: 'layer:aabbs', help: 'Debug: bounding boxes' },
  { keys: ['d'], action: 'layer:ids', help: 'Debug: body ids' },
  { keys: ['h', '?'], action: 'help', help: 'This help' },
  { keys: ['o'], action: 'lobby', help: 'Rooms (lobby)' },
  { keys: ['escape'], action: 'escape', help: 'Close panels, cancel, deselect' },
]

/**
 * The action for a key event, or null. With Ctrl or Cmd (Meta) held only the 'ctrl+' keys match
 * (Shift then counts: 'ctrl+shift+z'); keys with Alt held, and Ctrl or Cmd with any other key, are
 * ignored.
 */
export function shortcutFor(e: {
  key: string
  ctrlKey: boolean
  altKey: boolean
  metaKey: boolean
  shiftKey?: boolean
}): ShortcutAction | null {
  if (e.altKey) return null
  let key = e.key.toLowerCase()
  if (e.ctrlKey || e.metaKey) key = `ctrl+${e.shiftKey ? 'shift+' : ''}${key}`
  return SHORTCUTS.find((s) => s.keys.includes(key))?.action ?? null
}

/** The joint tools (one row in the touch Help). */
const JOINT_TOOLS: readonly ShortcutAction[] = [
  'tool:weld',
  'tool:hinge',
  'tool:spring',
  'tool:slider',
  'tool:wheel',
]

/** The toolbar buttons of the room actions (the tools are named by their help's first word). */
const BUTTONS: Partial<Record<ShortcutAction, string>> = {
  pause: 'Pause',
  step: 'Step',
  reset: 'Reset',
  gravity: 'Gravity',
  fit: 'Fit',
  undo: 'Undo',
  redo: 'Redo',
}

/** Shorter help on a phone, where a row must fit one or two lines. */
const TOUCH_HELP: Partial<Record<ShortcutAction, string>> = {
  'tool:edit': 'tap a body to change it, drag it to move it; drag empty space to select several',
}

/** A key as Help shows it: 'Space', 'Esc', arrows as ←↑→↓, 'Ctrl/⌘+Z', letters in upper case. */
function keyLabel(k: string): string {
  if (k === ' ') return 'Space'
  if (k === 'escape') return 'Esc'
  if (ARROWS[k]) return ARROWS[k]
  return k
    .split('+')
    .map((part) => (part === 'ctrl' ? 'Ctrl/⌘' : part === 'shift' ? 'Shift' : part.toUpperCase()))
    .join('+')
}

const ARROWS: Record<string, string> = { arrowleft: '←', arrowup: '↑', arrowright: '→', arrowdown: '↓' }

const escapeHtml = (s: string): string => s.replace(/[&<>"']/g, (c) => `&#${c.charCodeAt(0)};`)

/**
 * Help's rows for a game: its keys (its client module's keysHelp, every bound key in some row;
 * not with `touch`) and its pointer gesture (pointer.help), under a heading row naming the game;
 * the text is the module's, escaped.
 */
export function gameHelpRows(client: GameClient, touch = false): string {
  const rows = touch
    ? []
    : (client.keysHelp ?? []).map(
        (row) =>
          `<tr class="game-key"><td>${row.keys.map((k) => `<kbd>${escapeHtml(keyLabel(k))}</kbd>`).join(' ')}</td><td>${escapeHtml(row.help)}</td></tr>`,
      )
  const pointer = client.pointer?.help
  if (pointer)
    rows.push(
      `<tr class="game-key"><td><b>${touch ? 'Tap' : 'Click'}</b></td><td>${escapeHtml(pointer)}</td></tr>`,
    )
  if (rows.length === 0) return ''
  const heading = `<b>${escapeHtml(client.game)}</b>${touch ? '' : ' keys'}`
  return `<tr class="game-keys"><td colspan="2">${heading}</td></tr>${rows.join('')}`
}

/**
 * The help overlay's HTML rows. With `touch` (a phone or tablet, no keyboard) only what has a
 * button, named as the button is, without keys: short enough to fit a phone's screen unscrolled.
 * With `game` (the room's game's client module), the game's rows come first (its keys only with a
 * keyboard), and the shortcuts lose the keys it binds (a shortcut left with none is not listed).
 */
export function helpRows(touch = false, game?: GameClient): string {
  const label = keyLabel
  if (touch) {
    const rows: string[] = []
    const joints: string[] = []
    for (const s of SHORTCUTS) {
      const tool = s.action.startsWith('tool:')
      // The joint tools share one row on a phone, so Help still fits its screen.
      if (JOINT_TOOLS.includes(s.action)) {
        joints.push(s.help.slice(0, s.help.indexOf(':')))
        if (joints.length === JOINT_TOOLS.length)
          rows.push(`<tr><td><b>Joints</b></td><td>${joints.join(', ')}</td></tr>`)
        continue
      }
      const button = tool ? s.help.slice(0, s.help.indexOf(':')) : BUTTONS[s.action]
      if (!button) continue
      // The three spawn tools share one row on a phone too.
      if (s.action === 'tool:box' || s.action === 'tool:polygon') continue
      if (s.action === 'tool:circle') {
        rows.push(
          '<tr><td><b>Circle</b>, <b>Box</b>, <b>Polygon</b></td><td>tap to drop one, drag to throw it</td></tr>',
        )
        continue
      }
      // Undo and redo share one row on a phone.
      if (s.action === 'undo') continue
      if (s.action === 'redo') {
        rows.push('<tr><td><b>Undo</b>, <b>Redo</b></td><td>your own last action</td></tr>')
        continue
      }
      // Pause and Step share one row on a phone.
      if (s.action === 'pause') continue
      if (s.action === 'step') {
        rows.push('<tr><td><b>Pause</b>, <b>Step</b></td><td>pause / resume; one step while paused</td></tr>')
        continue
      }
      const text = TOUCH_HELP[s.action] ?? (tool ? s.help.slice(s.help.indexOf(':') + 1).trim() : s.help)
      rows.push(`<tr><td><b>${button}</b></td><td>${text.replace(/^click/, 'tap')}</td></tr>`)
    }
    return (game ? gameHelpRows(game, true) : '') + rows.join('')
  }
  const taken = (k: string): boolean => game?.keys[k] !== undefined
  const shortcuts = SHORTCUTS.map((s) => ({ ...s, keys: s.keys.filter((k) => !taken(k)) }))
    .filter((s) => s.keys.length > 0)
    .map(
      (s) => `<tr><td>${s.keys.map((k) => `<kbd>${label(k)}</kbd>`).join(' ')}</td><td>${s.help}</td></tr>`,
    )
    .join('')
  return (game ? gameHelpRows(game) : '') + shortcuts
}

/** The help overlay's first paragraph, for a mouse and keyboard or for touch. */
export function helpIntro(touch = false): string {
  return touch
    ? 'Tap a tool, then tap the world; drag a body to throw it, drag empty space to pan, pinch to zoom. Everyone in the room sees the same world.'
    : 'Drag bodies to throw them; press on empty space to pan; wheel or pinch to zoom. Everyone in the room sees the same world: the server simulates it, your page draws it.'
}
