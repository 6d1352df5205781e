/*
 * A game without a view, loaded from a directory by tests/server/games/default-view.test.ts: each
 * player appends text to its page (`write`); the state holds every page. With no `view`, a snapshot
 * player's view is the whole state, until the pages pass MAX_VIEW_BYTES. It imports only the SDK,
 * as a game outside this repository would.
 */
import { defineGame, type PlainData } from 'concord/game'

interface Notebook {
  [key: string]: PlainData
  pages: Record<string, string> // player id -> its page
}

export default defineGame<Notebook>({
  name: 'notebook',
  maxPlayers: 8,
  state: { pages: {} },
  commands: {
    write: {
      args: {
        type: 'object',
        properties: { text: { type: 'string', maxLength: 1000 } },
        required: ['text'],
        additionalProperties: false,
      },
      apply(ctx, player, args: { text: string }) {
        ctx.state.pages[player] = (ctx.state.pages[player] ?? '') + args.text
      },
    },
  },
})
