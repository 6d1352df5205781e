/*
 * A game module imports straight into a vitest test, as docs/games.md says: vitest.config.ts maps
 * `concord/game` to games/sdk.ts as tsconfig.json's paths do for the type checker (vitest reads no
 * tsconfig paths; without the alias the import fails with "Cannot find package 'concord/game'").
 */
import { expect, it } from 'vitest'
import hoops from '../../examples/games/hoops/index.ts'

it('examples/games/hoops imports in a test through the concord/game alias', () => {
  expect(hoops.name).toBe('hoops')
  expect(Object.keys(hoops.commands)).toEqual(['shoot'])
})
