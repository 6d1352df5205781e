/*
 * The static determinism check of game modules (docs/games.md, "The determinism rules"), in the
 * spirit of Rune's: a game's rules run on the server and in every browser and must compute the
 * same thing everywhere, so its source may not reach for anything whose result depends on the
 * machine, the JavaScript engine, the time or the order of events. The check parses each file with
 * the TypeScript compiler and resolves identifiers with its binder and checker (a local variable
 * named `Date` is not the global one; a parameter shadowing a module-level name is not module
 * state), then names the file, line and rule of every break:
 *
 *   no-random      Math.random (use ctx.random)
 *   no-clock       Date, performance, process.hrtime
 *   no-timers      setTimeout, setInterval, setImmediate, queueMicrotask, requestAnimationFrame, ...
 *   no-async       async functions, await, Promise, generators' async forms
 *   inexact-math   Math functions other than sqrt abs min max floor ceil round sign trunc fround
 *                  imul (and constants), and the ** operator (use the engine's sin, cos, atan2)
 *   module-state   let or var at module level; assigning to, deleting from or calling a mutating
 *                  method (push, set, sort, ...) on a module-level binding or an import
 *   no-io          fetch, XMLHttpRequest, WebSocket, require, process, globalThis, window, document,
 *                  storage, dynamic import(), and imports of anything but relative modules and concord/game
 *   no-eval        eval, Function (new Function, Function())
 *   no-locale      Intl, localeCompare, toLocaleString and friends (they follow the machine's locale)
 *   no-this        `this` outside a class
 *
 * What a static check cannot see (a rule that iterates a Map filled in timing order, a value
 * smuggled in through ctx) the live hash checkpoints catch: say so in the docs. The TypeScript
 * compiler is a devDependency: only this file (server and test code) imports it, never games/ or
 * shared/.
 */
import { readdirSync, readFileSync } from 'node:fs'
import { join } from 'node:path'
import ts from 'typescript'

/** The one package name a game module may import: the game SDK (games/sdk.ts). */
export const GAME_SDK = 'concord/game'

/** A rule a game module broke. */
export type DeterminismRule =
  | 'no-random'
  | 'no-clock'
  | 'no-timers'
  | 'no-async'
  | 'inexact-math'
  | 'module-state'
  | 'no-io'
  | 'no-eval'
  | 'no-locale'
  | 'no-this'

/** One break: where (1-based line and column) and which rule, with a sentence saying what to do. */
export interface DeterminismViolation {
  file: string
  line: number
  column: number
  rule: DeterminismRule
  message: string
}

/** Math members with results that every JavaScript engine computes exactly alike. */
const EXACT_MATH = new Set([
  'sqrt',
  'abs',
  'min',
  'max',
  'floor',
  'ceil',
  'round',
  'sign',
  'trunc',
  'fround',
  'imul',
  'clz32',
  'PI',
  'E',
  'LN2',
  'LN10',
  'LOG2E',
  'LOG10E',
  'SQRT1_2',
  'SQRT2',
])

/** Global names a game may not use, with the rule and the advice. */
const FORBIDDEN_GLOBALS: Record<string, [DeterminismRule, string]> = {
  Date: ['no-clock', 'Date reads the clock: use ctx.tick (60 per second)'],
  performance: ['no-clock', 'performance reads the clock: use ctx.tick'],
  setTimeout: ['no-timers', 'timers run outside the tick: count ticks in ctx.state instead'],
  setInterval: ['no-timers', 'timers run outside the tick: count ticks in ctx.state instead'],
  setImmediate: ['no-timers', 'timers run outside the tick: count ticks in ctx.state instead'],
  clearTimeout: ['no-timers', 'timers run outside the tick: count ticks in ctx.state instead'],
  clearInterval: ['no-timers', 'timers run outside the tick: count ticks in ctx.state instead'],
  queueMicrotask: ['no-timers', 'microtasks run outside the tick'],
  requestAnimationFrame: ['no-timers', 'frames are not ticks: use tick(ctx)'],
  requestIdleCallback: ['no-timers', 'idle callbacks run outside the tick'],
  Promise: ['no-async', 'promises settle outside the tick: game code is synchronous'],
  fetch: ['no-io', 'game code does no I/O'],
  XMLHttpRequest: ['no-io', 'game code does no I/O'],
  WebSocket: ['no-io', 'game code does no I/O'],
  require: ['no-io', 'game code imports only engine/, shared/ and games/ modules'],
  process: ['no-io', 'process is Node-only and machine-dependent'],
  globalThis: ['no-io', 'globals are shared by every room: keep data in ctx.state'],
  window: ['no-io', 'globals are shared by every room: keep data in ctx.state'],
  self: ['no-io', 'globals are shared by every room: keep data in ctx.state'],
  document: ['no-io', 'game code does no I/O'],
  navigator: ['no-io', 'game code does no I/O'],
  localStorage: ['no-io', 'game code does no I/O'],
  sessionStorage: ['no-io', 'game code does no I/O'],
  indexedDB: ['no-io', 'game code does no I/O'],
  crypto: ['no-random', 'crypto randomness differs everywhere: use ctx.random'],
  eval: ['no-eval', 'eval runs code the check cannot see'],
  Function: ['no-eval', 'the Function constructor runs code the check cannot see'],
  Intl: ['no-locale', 'Intl follows the machine locale'],
}

/** Methods whose result follows the machine's locale. */
const LOCALE_METHODS = new Set([
  'localeCompare',
  'toLocaleString',
  'toLocaleDateString',
  'toLocaleTimeString',
  'toLocaleUpperCase',
  'toLocaleLowerCase',
])

/** Methods that change the object they are called on (arrays, maps, sets, typed arrays, dates). */
const MUTATORS = new Set([
  'push',
  'pop',
  'shift',
  'unshift',
  'splice',
  'sort',
  'reverse',
  'fill',
  'copyWithin',
  'set',
  'add',
  'delete',
  'clear',
])

/**
 * Check game modules given as (file name -> source text); returns every break in file order.
 * Files are parsed together so that imports between them resolve; nothing is read from disk.
 */
export function checkGameSources(files: ReadonlyMap<string, string>): DeterminismViolation[] {
  const options: ts.CompilerOptions = {
    target: ts.ScriptTarget.ES2022,
    module: ts.ModuleKind.ESNext,
    noLib: true,
    noResolve: true,
    allowJs: true,
    allowImportingTsExtensions: true,
    noEmit: true,
    types: [],
  }
  const host = ts.createCompilerHost(options)
  const originalGet = host.getSourceFile.bind(host)
  host.getSourceFile = (name, version, onError, create) => {
    const text = files.get(name)
    return text !== undefined
      ? ts.createSourceFile(name, text, version, true)
      : originalGet(name, version, onError, create)
  }
  host.fileExists = (name) => files.has(name)
  host.readFile = (name) => files.get(name)
  const program = ts.createProgram([...files.keys()], options, host)
  const checker = program.getTypeChecker()
  const found: DeterminismViolation[] = []
  for (const name of files.keys()) {
    const source = program.getSourceFile(name)
    if (source) found.push(...checkSourceFile(source, checker))
  }
  return found
}

function checkSourceFile(source: ts.SourceFile, checker: ts.TypeChecker): DeterminismViolation[] {
  const found: DeterminismViolation[] = []
  const report = (node: ts.Node, rule: DeterminismRule, message: string): void => {
    const { line, character } = source.getLineAndCharacterOfPosition(node.getStart(source))
    found.push({ file: source.fileName, line: line + 1, column: character + 1, rule, message })
  }

  /** The declaration an identifier refers to, or undefined for a global (or an unknown name). */
  const declarationOf = (id: ts.Identifier): ts.Declaration | undefined => {
    let symbol = checker.getSymbolAtLocation(id)
    if (symbol && id.parent && ts.isShorthandPropertyAssignment(id.parent))
      symbol = checker.getShorthandAssignmentValueSymbol(id.parent)
    return symbol?.declarations?.[0]
  }
  const isGlobal = (id: ts.Identifier): boolean => declarationOf(id) === undefined
  /** Whether a declaration sits at module level (a top-level variable, function, class or import). */
  const isModuleLevel = (decl: ts.Declaration): boolean => {
    if (ts.isImportSpecifier(decl) || ts.isImportClause(decl) || ts.isNamespaceImport(decl)) return true
    if (ts.isVariableDeclaration(decl)) {
      const statement = decl.parent?.parent
      return statement !== undefined && ts.isVariableStatement(statement) && statement.parent === source
    }
    return false
  }
  /** The identifier at the root of `a.b[c].d`, if any. */
  const rootOf = (expr: ts.Expression): ts.Identifier | undefined => {
    let e: ts.Expression = expr
    while (true) {
      if (ts.isPropertyAccessExpression(e) || ts.isElementAccessExpression(e)) e = e.expression
      else if (ts.isParenthesizedExpression(e) || ts.isNonNullExpression(e) || ts.isAsExpression(e))
        e = e.expression
      else break
    }
    return ts.isIdentifier(e) ? e : undefined
  }
  const checkMutation = (target: ts.Expression, node: ts.Node, what: string): void => {
    // Building a table while the module loads is the same everywhere; changing it later is not.
    if (!insideFunction(node)) return
    const root = rootOf(target)
    if (!root) return
    const decl = declarationOf(root)
    if (decl && isModuleLevel(decl))
      report(
        node,
        'module-state',
        `${what} module-level ${root.text}: rooms share the module; keep room data in ctx.state`,
      )
  }
  /** Whether `this` here is inside a class member (arrow functions pass `this` through). */
  const thisInClass = (node: ts.Node): boolean => {
    for (let n = node.parent; n; n = n.parent) {
      if (ts.isClassLike(n)) return true
      if (ts.isFunctionDeclaration(n) || ts.isFunctionExpression(n)) return false
      if (
        ts.isMethodDeclaration(n) ||
        ts.isGetAccessor(n) ||
        ts.isSetAccessor(n) ||
        ts.isConstructorDeclaration(n)
      )
        return ts.isClassLike(n.parent)
      if (ts.isPropertyDeclaration(n)) return true
    }
    return false
  }
  const isAssignment = (kind: ts.SyntaxKind): boolean =>
    kind >= ts.SyntaxKind.FirstAssignment && kind <= ts.SyntaxKind.LastAssignment

  const visit = (node: ts.Node): void => {
    // Module-level let and var.
    if (ts.isVariableStatement(node) && node.parent === source) {
      const flags = node.declarationList.flags
      if (!(flags & ts.NodeFlags.Const) && !(flags & ts.NodeFlags.Using))
        report(
          node,
          'module-state',
          `${flags & ts.NodeFlags.Let ? 'let' : 'var'} at module level: rooms share the module; keep room data in ctx.state`,
        )
    }
    // Imports: relative modules and the game SDK only.
    if (ts.isImportDeclaration(node) || ts.isExportDeclaration(node)) {
      const spec = node.moduleSpecifier
      if (spec && ts.isStringLiteral(spec) && !spec.text.startsWith('.') && spec.text !== GAME_SDK)
        report(
          node,
          'no-io',
          `imports '${spec.text}': game code imports only its own files, '${GAME_SDK}', and engine/, shared/ and games/ modules`,
        )
    }
    if (ts.isCallExpression(node) && node.expression.kind === ts.SyntaxKind.ImportKeyword)
      report(node, 'no-io', 'dynamic import() loads code outside the tick')
    // async, await, generators' async forms.
    if (
      ts.isFunctionLike(node) &&
      ts.canHaveModifiers(node) &&
      ts.getModifiers(node)?.some((m) => m.kind === ts.SyntaxKind.AsyncKeyword)
    )
      report(node, 'no-async', 'async functions settle outside the tick: game code is synchronous')
    if (ts.isAwaitExpression(node) || (ts.isForOfStatement(node) && node.awaitModifier))
      report(node, 'no-async', 'await waits outside the tick: game code is synchronous')
    // this outside a class.
    if (node.kind === ts.SyntaxKind.ThisKeyword && !thisInClass(node))
      report(node, 'no-this', '`this` outside a class: use ctx and plain functions')
    // The ** operator is Math.pow.
    if (
      ts.isBinaryExpression(node) &&
      (node.operatorToken.kind === ts.SyntaxKind.AsteriskAsteriskToken ||
        node.operatorToken.kind === ts.SyntaxKind.AsteriskAsteriskEqualsToken)
    )
      report(
        node.operatorToken,
        'inexact-math',
        '** is Math.pow, whose results differ between engines: multiply',
      )
    // Math members.
    if (
      ts.isPropertyAccessExpression(node) &&
      ts.isIdentifier(node.expression) &&
      node.expression.text === 'Math' &&
      isGlobal(node.expression)
    ) {
      const member = node.name.text
      if (member === 'random') report(node, 'no-random', 'Math.random differs everywhere: use ctx.random')
      else if (!EXACT_MATH.has(member))
        report(
          node,
          'inexact-math',
          `Math.${member} differs between JavaScript engines: use the engine's sin, cos and atan2, or + - * / and Math.sqrt`,
        )
    }
    if (
      ts.isElementAccessExpression(node) &&
      ts.isIdentifier(node.expression) &&
      node.expression.text === 'Math' &&
      isGlobal(node.expression)
    )
      report(node, 'inexact-math', 'Math[...] hides which function is called: name it')
    // Forbidden globals.
    if (
      ts.isIdentifier(node) &&
      Object.hasOwn(FORBIDDEN_GLOBALS, node.text) &&
      isReference(node) &&
      isGlobal(node)
    ) {
      const [rule, advice] = FORBIDDEN_GLOBALS[node.text]
      report(node, rule, `${node.text}: ${advice}`)
    }
    // Locale-dependent methods.
    if (ts.isPropertyAccessExpression(node) && LOCALE_METHODS.has(node.name.text))
      report(node.name, 'no-locale', `${node.name.text} follows the machine locale: compare with < and >`)
    // Mutating module-level bindings.
    if (ts.isBinaryExpression(node) && isAssignment(node.operatorToken.kind))
      checkMutation(node.left, node, 'assigns to')
    if (
      (ts.isPrefixUnaryExpression(node) || ts.isPostfixUnaryExpression(node)) &&
      (node.operator === ts.SyntaxKind.PlusPlusToken || node.operator === ts.SyntaxKind.MinusMinusToken)
    )
      checkMutation(node.operand, node, 'changes')
    if (ts.isDeleteExpression(node)) checkMutation(node.expression, node, 'deletes from')
    if (
      ts.isCallExpression(node) &&
      ts.isPropertyAccessExpression(node.expression) &&
      MUTATORS.has(node.expression.name.text)
    ) {
      checkMutation(node.expression.expression, node, `calls ${node.expression.name.text} on`)
    }
    if (
      ts.isCallExpression(node) &&
      ts.isPropertyAccessExpression(node.expression) &&
      ts.isIdentifier(node.expression.expression) &&
      node.expression.expression.text === 'Object' &&
      ['assign', 'defineProperty', 'setPrototypeOf'].includes(node.expression.name.text) &&
      node.arguments.length > 0
    )
      checkMutation(node.arguments[0], node, `Object.${node.expression.name.text} changes`)
    ts.forEachChild(node, visit)
  }
  visit(source)
  return found
}

/** Whether a node runs inside a function (not while the module loads). */
function insideFunction(node: ts.Node): boolean {
  for (let n = node.parent; n; n = n.parent)
    if (ts.isFunctionLike(n) || ts.isClassStaticBlockDeclaration(n)) return true
  return false
}

/** Whether an identifier is a reference to a binding (not a property name, a key or a declaration's name). */
function isReference(id: ts.Identifier): boolean {
  const p = id.parent
  if (!p) return true
  if (ts.isPropertyAccessExpression(p) && p.name === id) return false
  if (
    (ts.isPropertyAssignment(p) || ts.isPropertyDeclaration(p) || ts.isMethodDeclaration(p)) &&
    p.name === id
  )
    return false
  if (
    (ts.isPropertySignature(p) || ts.isMethodSignature(p) || ts.isGetAccessor(p) || ts.isSetAccessor(p)) &&
    p.name === id
  )
    return false
  if (ts.isQualifiedName(p) && p.right === id) return false
  if (ts.isTypeReferenceNode(p)) return false
  if (ts.isImportSpecifier(p) || ts.isExportSpecifier(p)) return false
  if (ts.isLabeledStatement(p) || ts.isBreakOrContinueStatement(p)) return false
  return true
}

/** One line for a violation: "file:line:column rule: message". */
export function formatViolation(v: DeterminismViolation): string {
  return `${v.file}:${v.line}:${v.column} ${v.rule}: ${v.message}`
}

/** The game module files under a directory: every .ts or .js file in its sub-folders (one folder per game). */
export function gameModuleFiles(dir: string): string[] {
  const out: string[] = []
  for (const entry of readdirSync(dir, { withFileTypes: true })) {
    if (!entry.isDirectory()) continue
    const folder = join(dir, entry.name)
    for (const file of readdirSync(folder, { recursive: true, encoding: 'utf8' }).sort())
      if (/\.(ts|js)$/.test(file) && !file.endsWith('.d.ts')) out.push(join(folder, file))
  }
  return out.sort()
}

/** Check the game modules under a directory (gameModuleFiles), read from disk. */
export function checkGameDirectory(dir: string): DeterminismViolation[] {
  const files = new Map<string, string>()
  for (const file of gameModuleFiles(dir)) files.set(file, readFileSync(file, 'utf8'))
  return checkGameSources(files)
}
