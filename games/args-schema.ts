/*
 * Game command arguments are described in JSON Schema (draft 2020-12's vocabulary as Ajv 8 reads
 * it: type, properties, required, additionalProperties, minimum, maximum, enum, minItems,
 * maxItems, maxLength, ...) and checked with Ajv before a game sees them. Ajv compiles each schema
 * once, when the game is defined; a check then costs well under a microsecond for a small map
 * (docs/games.md gives the measured figure). Ajv 8 refuses NaN and the infinities as numbers
 * (strictNumbers), so a checked number is always finite.
 *
 * The rest of the code sees only ArgsChecker: a function that names the first field that is
 * wrong, or returns null. Another validator (TypeBox's, a hand-written one) could stand in.
 */
import { Ajv, type ErrorObject } from 'ajv'

/** A JSON Schema for a command's arguments: always an object (a map on the wire). */
export interface ArgsSchema {
  type: 'object'
  properties?: Record<string, object>
  required?: readonly string[]
  additionalProperties?: boolean | object
  [keyword: string]: unknown
}

/** Checks decoded arguments: null when they fit the schema, else what is wrong, naming the field. */
export type ArgsChecker = (args: unknown) => string | null

const ajv = new Ajv({ allErrors: false, strict: true, coerceTypes: false, useDefaults: false })

/** Where an Ajv error is, as a field path ("power", "to[1]") or "arguments" for the whole map. */
function fieldOf(error: ErrorObject): string {
  const path = error.instancePath
    .split('/')
    .slice(1)
    .map((part) => (/^\d+$/.test(part) ? `[${part}]` : `.${part}`))
    .join('')
    .replace(/^\./, '')
  const extra = error.params as { missingProperty?: string; additionalProperty?: string }
  const child = extra.missingProperty ?? extra.additionalProperty
  if (child !== undefined) return path ? `${path}.${child}` : child
  return path || 'arguments'
}

/** One line for an Ajv error: "power must be <= 10", "power is required", "z is not allowed". */
function describe(error: ErrorObject): string {
  const field = fieldOf(error)
  if (error.keyword === 'required') return `${field} is required`
  if (error.keyword === 'additionalProperties') return `${field} is not allowed`
  return `${field} ${error.message ?? 'is invalid'}`
}

/** Compile a schema into a checker; throws a RangeError naming the command for a bad schema. */
export function compileArgs(kind: string, schema: ArgsSchema): ArgsChecker {
  if (typeof schema !== 'object' || schema === null || schema.type !== 'object')
    throw new RangeError(`command ${kind}: its args schema must be a JSON Schema of type 'object'`)
  let validate: ReturnType<Ajv['compile']>
  try {
    validate = ajv.compile(schema)
  } catch (error) {
    throw new RangeError(`command ${kind}: bad args schema: ${(error as Error).message}`)
  }
  return (args) => {
    if (validate(args)) return null
    const first = validate.errors?.[0]
    return first ? describe(first) : 'arguments are invalid'
  }
}
