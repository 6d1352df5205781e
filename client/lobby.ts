/*
 * The lobby: the server's open rooms (GET /rooms: name, players, bodies, scene, tick) as links,
 * plus a field to open a new room by name. Room links are ordinary URLs (?room=NAME), so sharing
 * the address bar invites a friend to the same room.
 */
import { ROOM_NAME_PATTERN } from '../shared/index.ts'

/** One row of GET /rooms. */
export interface RoomInfo {
  name: string
  players: number
  bodies: number
  scene: string
}

/** The URL of a room on this page (the access key and player name carried over). */
export function roomLink(room: string): string {
  return pageLink({ room })
}

/** The URL of the replay picker on this page (the access key carried over: a token-only server's replays need it). */
export function replaysLink(): string {
  return pageLink({ replay: '' })
}

/**
 * The URL of this page in offline mode with `scene`, remembering the room it came from, so that
 * going back online returns to the same room.
 */
export function offlineLink(room: string, scene: string): string {
  return pageLink({ offline: '', room, scene })
}

/** This page's URL with these parameters, plus the current key and name if any. */
function pageLink(params: Record<string, string>): string {
  const url = new URL(location.href)
  const keep = new URLSearchParams(params)
  for (const name of ['key', 'name']) {
    const value = url.searchParams.get(name)
    if (value) keep.set(name, value)
  }
  url.search = `?${keep.toString().replace(/^(offline|replay)=(&|$)/, '$1$2')}`
  return url.toString()
}

/**
 * Fetch the room list, with the page's access key (a server with a join token lists its rooms only
 * to a key holder); throws with a readable message when the server cannot be reached or refuses.
 */
export async function fetchRooms(base: string): Promise<RoomInfo[]> {
  const key = new URL(location.href).searchParams.get('key')
  let response: Response
  try {
    response = await fetch(`${base}/rooms${key ? `?key=${encodeURIComponent(key)}` : ''}`, {
      cache: 'no-store',
    })
  } catch {
    throw new Error('The server cannot be reached, so there is no room list. Offline mode still works.')
  }
  if (response.status === 401) throw new Error('This server lists its rooms only to players with its key.')
  if (!response.ok) throw new Error(`The server answered /rooms with HTTP ${response.status}.`)
  const rows = (await response.json()) as unknown
  if (!Array.isArray(rows)) throw new Error('The server sent a room list this client does not understand.')
  return rows.filter((r): r is RoomInfo => typeof r?.name === 'string' && typeof r?.players === 'number')
}

const escapeHtml = (s: string): string => s.replace(/[&<>"']/g, (c) => `&#${c.charCodeAt(0)};`)

/** Fill the lobby element with the room list (or an error) and a new-room form. */
export async function showLobby(list: HTMLElement, base: string, current: string): Promise<void> {
  list.textContent = 'Loading rooms…'
  try {
    const rooms = await fetchRooms(base)
    rooms.sort((a, b) => b.players - a.players || a.name.localeCompare(b.name))
    list.innerHTML = rooms.length
      ? `<table><tr><th>room</th><th>players</th><th>bodies</th><th>scene</th></tr>${rooms
          .map(
            (r) =>
              `<tr${r.name === current ? ' class="current"' : ''}><td><a href="${escapeHtml(roomLink(r.name))}">${escapeHtml(
                r.name,
              )}</a></td><td>${r.players}</td><td>${r.bodies}</td><td>${escapeHtml(r.scene)}</td></tr>`,
          )
          .join('')}</table>`
      : 'No rooms are open.'
  } catch (error) {
    list.textContent = (error as Error).message
  }
}

/** A valid room name from user text, or null. */
export function cleanRoomName(text: string): string | null {
  const name = text.trim().replace(/\s+/g, '-')
  return ROOM_NAME_PATTERN.test(name) ? name : null
}
