/*
 * Hostile game command arguments (issue 29): fast-check builds `cmd` messages whose `k` and `a`
 * are anything MessagePack can carry (wrong types, NaN and infinities, huge strings, deep nesting,
 * unknown kinds, missing and extra fields, binary). Each goes through the protocol's validation
 * and then the game's schema check, as the server does; whatever passes both must satisfy ball
 * drop's `drop` schema by an independent check written here, and a refusal always has a reason.
 * The server's encoder is not in the way: values are handed to validateClientMessage as decoded.
 */
import fc from 'fast-check'
import { describe, expect, it } from 'vitest'
import { ballDrop } from '../../games/index.ts'
import { validateClientMessage } from '../../shared/index.ts'

/** Ball drop's drop arguments by hand: a map holding exactly a finite number x in [-8, 8]. */
const dropArgsOk = (a: unknown): boolean =>
  typeof a === 'object' &&
  a !== null &&
  !Array.isArray(a) &&
  Object.keys(a).length === 1 &&
  typeof (a as { x?: unknown }).x === 'number' &&
  Number.isFinite((a as { x: number }).x) &&
  Math.abs((a as { x: number }).x) <= 8

const anyValue = fc.letrec((tie) => ({
  value: fc.oneof(
    { depthSize: 'small' },
    fc.constantFrom(null, undefined, true, false, Number.NaN, Number.POSITIVE_INFINITY, -0, 1e308),
    fc.double(),
    fc.integer(),
    fc.string({ maxLength: 2000 }),
    fc.uint8Array({ maxLength: 8 }),
    fc.array(tie('value'), { maxLength: 4 }),
    fc.dictionary(fc.string({ maxLength: 40 }), tie('value'), { maxKeys: 4 }),
  ),
})).value

const args = fc.oneof(
  anyValue,
  fc.record({ x: anyValue }),
  fc.record({ x: fc.double() }),
  fc.record({ x: fc.double({ min: -10, max: 10 }), extra: anyValue }, { requiredKeys: ['x'] }),
)

describe('hostile game command arguments', () => {
  it('reach the game only when they fit its schema; everything else is refused with a reason', () => {
    let reached = 0
    fc.assert(
      fc.property(fc.oneof(fc.constant('drop'), fc.string({ maxLength: 40 })), args, (k, a) => {
        const checked = validateClientMessage({ t: 'cmd', seq: 1, k, a })
        if (!checked.ok) {
          expect(checked.reason.length).toBeGreaterThan(0)
          return
        }
        if (checked.value.t !== 'cmd') throw new Error('not a cmd')
        const def = Object.hasOwn(ballDrop.commands, checked.value.k)
          ? ballDrop.commands[checked.value.k]
          : undefined
        if (!def || def.builtin) return
        const refusal = def.check(checked.value.a)
        if (refusal !== null) {
          expect(refusal).toMatch(/\S/)
          expect(dropArgsOk(checked.value.a)).toBe(false)
          return
        }
        reached++
        expect(dropArgsOk(checked.value.a)).toBe(true)
      }),
      { numRuns: 3000, seed: 29 },
    )
    // The generator does produce valid drops (the property is not vacuous).
    expect(reached).toBeGreaterThan(50)
  })
})
