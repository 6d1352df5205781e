/*
 * Renaming a player (the room command `rename`, PROTOCOL.md "Room commands"): a player's name is
 * the room's, not the simulation's (no replica needs it, the state hash does not hold it), so a
 * rename is applied by the room at the tick, outside the tick stream, and every player gets the
 * new roster (`players`). A name is checked as a join's is: at most MAX_NAME_LENGTH characters,
 * control characters dropped; it must hold something besides spaces.
 */
import { MAX_NAME_LENGTH, type PlainData } from '../../shared/index.ts'

/** The room command kind that renames its sender. */
export const RENAME = 'rename'

/** The name `rename`'s arguments give, or why they are refused (naming the field). */
export function renameArgs(args: PlainData): { name: string } | { error: string } {
  const a = args as Record<string, PlainData>
  for (const key of Object.keys(a)) if (key !== 'name') return { error: `${key} is not allowed` }
  if (typeof a.name !== 'string' || a.name.length > MAX_NAME_LENGTH)
    return { error: `name must be a string of at most ${MAX_NAME_LENGTH} characters` }
  // biome-ignore lint/suspicious/noControlCharactersInRegex: control characters are what we drop
  const name = a.name.replace(/[\u0000-\u001f\u007f]/g, '').trim()
  return name === '' ? { error: 'name must hold something besides spaces' } : { name }
}
