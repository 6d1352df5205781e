/*
 * A small Dockerfile reader for the image tests: joins continuation lines, drops comments and
 * parser directives, and splits the file into stages of (instruction, arguments). It knows only
 * what the image tests replay or check (FROM, WORKDIR, ENV, COPY, RUN, USER, VOLUME, EXPOSE,
 * HEALTHCHECK, CMD) and throws on anything else, so a new instruction in docker/Dockerfile cannot
 * be silently skipped.
 */
import { readFileSync } from 'node:fs'

/** One instruction: its keyword (upper case) and the rest of the line. */
export interface Instruction {
  op: string
  args: string
}

/** One build stage. */
export interface Stage {
  name: string
  image: string
  instructions: Instruction[]
}

const KNOWN = new Set([
  'FROM',
  'WORKDIR',
  'ENV',
  'COPY',
  'RUN',
  'USER',
  'VOLUME',
  'EXPOSE',
  'HEALTHCHECK',
  'CMD',
])

/** Parse a Dockerfile into stages; throws naming an instruction the tests do not know. */
export function readDockerfile(path: string): Stage[] {
  const lines = readFileSync(path, 'utf8').split('\n')
  const logical: string[] = []
  let pending = ''
  for (const raw of lines) {
    const line = raw.trimEnd()
    if (pending === '' && /^\s*#/.test(line)) continue
    if (line.endsWith('\\')) {
      pending += `${line.slice(0, -1)} `
      continue
    }
    const full = (pending + line).trim()
    pending = ''
    if (full !== '') logical.push(full)
  }
  const stages: Stage[] = []
  for (const line of logical) {
    const match = /^(\w+)\s+(.*)$/.exec(line)
    if (!match) throw new Error(`Dockerfile line not understood: "${line}"`)
    const op = match[1].toUpperCase()
    const args = match[2]
    if (!KNOWN.has(op)) throw new Error(`Dockerfile instruction ${op} is not replayed by the image tests`)
    if (op === 'FROM') {
      const from = /^(\S+)(?:\s+AS\s+(\S+))?$/i.exec(args)
      if (!from) throw new Error(`FROM line not understood: "${args}"`)
      stages.push({ image: from[1], name: from[2] ?? String(stages.length), instructions: [] })
      continue
    }
    if (stages.length === 0) throw new Error(`${op} before FROM`)
    stages[stages.length - 1].instructions.push({ op, args })
  }
  return stages
}

/** Split leading `--flag=value` options off an instruction's arguments. */
export function splitFlags(args: string): { flags: Map<string, string>; rest: string } {
  const flags = new Map<string, string>()
  let rest = args
  for (;;) {
    const match = /^--([\w-]+)(?:=(\S+))?\s+/.exec(rest)
    if (!match) return { flags, rest }
    flags.set(match[1], match[2] ?? '')
    rest = rest.slice(match[0].length)
  }
}

/** The argument array of an exec-form (JSON) CMD or HEALTHCHECK CMD; throws for shell form. */
export function execForm(args: string): string[] {
  const parsed: unknown = JSON.parse(args)
  if (!Array.isArray(parsed) || !parsed.every((x) => typeof x === 'string')) {
    throw new Error(`expected an exec-form JSON array of strings, got ${args}`)
  }
  return parsed
}

/** `ENV A=1 B=2` as pairs (values without spaces or quotes, which is all the Dockerfile uses). */
export function envPairs(args: string): Array<[string, string]> {
  return args.split(/\s+/).map((pair) => {
    const eq = pair.indexOf('=')
    if (eq <= 0) throw new Error(`ENV pair not understood: "${pair}"`)
    return [pair.slice(0, eq), pair.slice(eq + 1)]
  })
}
