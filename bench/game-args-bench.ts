/*
 * What checking a game command's arguments against its JSON Schema costs (issue 29): the
 * schema checker's check of ball drop's `drop` schema, and of a larger schema (a vector, an enum, an
 * integer, a short string), per call, valid and invalid arguments. Prints ns per check; run with
 * `npx tsx bench/game-args-bench.ts`.
 */
import { ballDrop, compileArgs } from '../games/index.ts'

const drop = ballDrop.commands.drop
const kick = compileArgs('kick', {
  type: 'object',
  properties: {
    to: { type: 'array', items: { type: 'number', minimum: -50, maximum: 50 }, minItems: 2, maxItems: 2 },
    foot: { enum: ['left', 'right'] },
    power: { type: 'integer', minimum: 1, maximum: 10 },
    note: { type: 'string', maxLength: 16 },
  },
  required: ['to', 'foot', 'power'],
  additionalProperties: false,
})

function time(what: string, check: (a: unknown) => string | null, args: unknown[]): void {
  const n = 2_000_000
  let refused = 0
  for (let i = 0; i < 200_000; i++) if (check(args[i % args.length]) !== null) refused++
  const start = process.hrtime.bigint()
  for (let i = 0; i < n; i++) if (check(args[i % args.length]) !== null) refused++
  const ns = Number(process.hrtime.bigint() - start) / n
  console.log(
    `${what.padEnd(34)} ${ns.toFixed(1).padStart(7)} ns per check (${refused > 0 ? 'refusing' : 'accepting'})`,
  )
}

time('drop {x}, valid', (a) => drop.check(a), [{ x: 1.5 }, { x: -3 }])
time('drop {x}, x out of range', (a) => drop.check(a), [{ x: 99 }])
time('kick {to, foot, power, note}, valid', kick, [{ to: [1, 2], foot: 'left', power: 5, note: 'hi' }])
time('kick, bad enum', kick, [{ to: [1, 2], foot: 'head', power: 5 }])
