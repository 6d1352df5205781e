/*
 * Game command arguments are described in JSON Schema (draft 2020-12) and checked with
 * @cfworker/json-schema before a game sees them. That validator interprets the schema instead of
 * generating code, so the same checker runs on the server and, unchanged, in a browser page whose
 * Content Security Policy forbids eval (Ajv compiles schemas with `new Function`, which such a page
 * refuses). One validator everywhere also means one answer everywhere: a command the server
 * accepts is accepted by every lockstep and predicting client and by the replay tool.
 *
 * A schema is checked once, when the game is defined: it must be an object schema and use only
 * the keywords listed in SCHEMA_KEYWORDS with well-formed values (an unknown keyword or a typo in
 * a type is an error, as in Ajv's strict mode). Numbers that pass are finite: NaN and the
 * infinities are refused before the schema is consulted (the wire cannot carry them either).
 * docs/games.md gives the measured cost of a check (bench/game-args-bench.ts).
 *
 * The rest of the code sees only ArgsChecker: a function that names the first field that is
 * wrong, or returns null.
 */
import { type OutputUnit, type Schema, Validator } from '@cfworker/json-schema'

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

const TYPES = new Set(['object', 'array', 'string', 'number', 'integer', 'boolean', 'null'])
const COUNT = (v: unknown) => Number.isInteger(v) && (v as number) >= 0
const NUMBER = (v: unknown) => typeof v === 'number' && Number.isFinite(v)
const SCHEMA = (v: unknown) =>
  typeof v === 'boolean' || (typeof v === 'object' && v !== null && !Array.isArray(v))

/** The keywords a command schema may use, each with a check of its value. */
const SCHEMA_KEYWORDS: Record<string, (value: unknown) => boolean> = {
  $schema: (v) => typeof v === 'string',
  $comment: (v) => typeof v === 'string',
  title: (v) => typeof v === 'string',
  description: (v) => typeof v === 'string',
  type: (v) => (Array.isArray(v) ? v.length > 0 && v.every((t) => TYPES.has(t)) : TYPES.has(v as string)),
  enum: (v) => Array.isArray(v) && v.length > 0,
  const: () => true,
  properties: (v) => SCHEMA(v) && typeof v === 'object',
  required: (v) => Array.isArray(v) && v.every((k) => typeof k === 'string'),
  additionalProperties: SCHEMA,
  minProperties: COUNT,
  maxProperties: COUNT,
  items: SCHEMA,
  prefixItems: (v) => Array.isArray(v) && v.every(SCHEMA),
  minItems: COUNT,
  maxItems: COUNT,
  uniqueItems: (v) => typeof v === 'boolean',
  minimum: NUMBER,
  maximum: NUMBER,
  exclusiveMinimum: NUMBER,
  exclusiveMaximum: NUMBER,
  multipleOf: (v) => NUMBER(v) && (v as number) > 0,
  minLength: COUNT,
  maxLength: COUNT,
  pattern: (v) => typeof v === 'string',
  anyOf: (v) => Array.isArray(v) && v.length > 0 && v.every(SCHEMA),
  oneOf: (v) => Array.isArray(v) && v.length > 0 && v.every(SCHEMA),
  allOf: (v) => Array.isArray(v) && v.length > 0 && v.every(SCHEMA),
  not: SCHEMA,
}

/** Where the schema first goes wrong ("properties.p.type: 'nmber'"), or null when it is well-formed. */
function schemaProblem(schema: unknown, at: string): string | null {
  if (typeof schema === 'boolean') return null
  if (typeof schema !== 'object' || schema === null || Array.isArray(schema))
    return `${at || 'schema'} is not a schema`
  for (const [keyword, value] of Object.entries(schema)) {
    const path = at ? `${at}.${keyword}` : keyword
    const check = Object.hasOwn(SCHEMA_KEYWORDS, keyword) ? SCHEMA_KEYWORDS[keyword] : undefined
    if (!check) return `unknown keyword ${path}`
    if (!check(value)) return `${path} has a bad value ${JSON.stringify(value)}`
    if (keyword === 'pattern') {
      try {
        new RegExp(value as string, 'u')
      } catch {
        return `${path} is not a regular expression`
      }
    }
    const children =
      keyword === 'properties'
        ? Object.entries(value as object)
        : keyword === 'items' || keyword === 'additionalProperties' || keyword === 'not'
          ? [['', value]]
          : keyword === 'prefixItems' || keyword === 'anyOf' || keyword === 'oneOf' || keyword === 'allOf'
            ? (value as unknown[]).map((s, i) => [String(i), s])
            : []
    for (const [name, child] of children) {
      const problem = schemaProblem(child, name ? `${path}.${name}` : path)
      if (problem) return problem
    }
  }
  return null
}

/** The first non-finite number in decoded arguments, as a field path, or null. */
function nonFinite(value: unknown, at: string, depth: number): string | null {
  if (typeof value === 'number') return Number.isFinite(value) ? null : at || 'arguments'
  if (typeof value !== 'object' || value === null || depth > 16) return null
  if (Array.isArray(value)) {
    for (let i = 0; i < value.length; i++) {
      const found = nonFinite(value[i], `${at}[${i}]`, depth + 1)
      if (found) return found
    }
    return null
  }
  for (const key of Object.keys(value)) {
    const found = nonFinite((value as Record<string, unknown>)[key], at ? `${at}.${key}` : key, depth + 1)
    if (found) return found
  }
  return null
}

/** An output unit's instance location ("#/to/1") as a field path ("to[1]"), or "arguments". */
function fieldOf(location: string): string {
  const path = location
    .split('/')
    .slice(1)
    .map((part) => decodeURIComponent(part).replace(/~1/g, '/').replace(/~0/g, '~'))
    .map((part) => (/^\d+$/.test(part) ? `[${part}]` : `.${part}`))
    .join('')
    .replace(/^\./, '')
  return path || 'arguments'
}

/** The schema value at a keyword location ("#/properties/n/maximum"). */
function schemaAt(schema: unknown, location: string): unknown {
  let node = schema
  for (const part of location.split('/').slice(1)) {
    if (typeof node !== 'object' || node === null) return undefined
    node = (node as Record<string, unknown>)[decodeURIComponent(part).replace(/~1/g, '/').replace(/~0/g, '~')]
  }
  return node
}

const QUOTED = /"([^"]*)"/

/** One line for the innermost error: "power must be <= 10", "power is required", "z is not allowed". */
function describe(schema: ArgsSchema, errors: readonly OutputUnit[]): string {
  const unit = errors[errors.length - 1]
  const field = fieldOf(unit.instanceLocation)
  const value = schemaAt(schema, unit.keywordLocation)
  const named = (unit.error.match(QUOTED) ?? [])[1]
  const child = (name: string | undefined) => (field === 'arguments' ? name : `${field}.${name}`)
  switch (unit.keyword) {
    case 'required':
      return `${child(named)} is required`
    case 'false':
    case 'additionalProperties':
      // A property refused by `additionalProperties: false` shows as a false schema at its own path.
      return unit.keyword === 'false' ? `${field} is not allowed` : `${child(named)} is not allowed`
    case 'type':
      return `${field} must be ${Array.isArray(value) ? value.join(',') : value}`
    case 'maximum':
      return `${field} must be <= ${value}`
    case 'minimum':
      return `${field} must be >= ${value}`
    case 'exclusiveMaximum':
      return `${field} must be < ${value}`
    case 'exclusiveMinimum':
      return `${field} must be > ${value}`
    case 'multipleOf':
      return `${field} must be a multiple of ${value}`
    case 'maxLength':
      return `${field} must NOT have more than ${value} characters`
    case 'minLength':
      return `${field} must NOT have fewer than ${value} characters`
    case 'maxItems':
      return `${field} must NOT have more than ${value} items`
    case 'minItems':
      return `${field} must NOT have fewer than ${value} items`
    case 'maxProperties':
      return `${field} must NOT have more than ${value} properties`
    case 'minProperties':
      return `${field} must NOT have fewer than ${value} properties`
    case 'enum':
      return `${field} must be equal to one of the allowed values`
    case 'const':
      return `${field} must be equal to constant`
    case 'pattern':
      return `${field} must match pattern "${value}"`
    case 'uniqueItems':
      return `${field} must NOT have duplicate items`
    default:
      return `${field} does not match the schema (${unit.keyword})`
  }
}

/** Compile a schema into a checker; throws a RangeError naming the command for a bad schema. */
export function compileArgs(kind: string, schema: ArgsSchema): ArgsChecker {
  if (typeof schema !== 'object' || schema === null || schema.type !== 'object')
    throw new RangeError(`command ${kind}: its args schema must be a JSON Schema of type 'object'`)
  const problem = schemaProblem(schema, '')
  if (problem) throw new RangeError(`command ${kind}: bad args schema: ${problem}`)
  const validator = new Validator(schema as Schema, '2020-12', true)
  return (args) => {
    const bad = nonFinite(args, '', 0)
    if (bad !== null) return `${bad} must be a finite number`
    const result = validator.validate(args)
    return result.valid ? null : describe(schema, result.errors)
  }
}
