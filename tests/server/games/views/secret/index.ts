/*
 * A game with a per-player view, loaded from a directory by tests/server/rooms/game-view.test.ts:
 * each player picks a secret number (`pick`) and may add to its note (`note`); the state holds every
 * player's, the view shows a player only its own secret and note and how many players picked. It
 * imports only the SDK, as a game outside this repository would.
 */
import { defineGame, type PlainData } from 'concord/game'

interface Secrets {
  [key: string]: PlainData
  secrets: Record<string, number> // player id -> secret
  notes: Record<string, string> // player id -> note
}

export default defineGame<Secrets>({
  name: 'secret',
  maxPlayers: 8,
  state: { secrets: {}, notes: {} },
  commands: {
    pick: {
      args: {
        type: 'object',
        properties: { n: { type: 'integer', minimum: 0, maximum: 999999 } },
        required: ['n'],
        additionalProperties: false,
      },
      apply(ctx, player, args: { n: number }) {
        ctx.state.secrets[player] = args.n
      },
    },
    note: {
      args: {
        type: 'object',
        properties: { text: { type: 'string', maxLength: 1000 } },
        required: ['text'],
        additionalProperties: false,
      },
      apply(ctx, player, args: { text: string }) {
        ctx.state.notes[player] = (ctx.state.notes[player] ?? '') + args.text
      },
    },
  },
  onLeave(ctx, player) {
    delete ctx.state.secrets[player]
    delete ctx.state.notes[player]
  },
  view(ctx, player) {
    return {
      secret: ctx.state.secrets[player] ?? null,
      note: ctx.state.notes[player] ?? '',
      picked: Object.keys(ctx.state.secrets).length,
    }
  },
})
