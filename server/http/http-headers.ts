/*
 * The security headers sent with every HTTP answer of the server: pages, scripts, the replay logs,
 * the JSON routes, probes and refusals alike (issue 30, point 11). Keys travel in page URLs
 * (`?key=KEY`), so no page may leak its URL to another site (Referrer-Policy) or be framed by one
 * (frame-ancestors, X-Frame-Options for older browsers), and nothing is sniffed into another type.
 *
 * The Content-Security-Policy is the narrowest one the built client runs under, checked in
 * Chromium by tests/browser/security-headers.test.ts (no CSP violation on the sandbox, lobby,
 * replay and benchmark pages):
 * - scripts only from this origin (the client is one module, app.js; the benchmark page's peer
 *   engines compile WebAssembly, hence 'wasm-unsafe-eval', which allows no JavaScript eval);
 * - styles from this origin plus inline ones: the page's own <style> and a few style attributes
 *   (no script can run from a style);
 * - WebSockets to any host (ws:, wss:): a `moved` answer sends the client to another server of the
 *   directory, whose URL only the server knows; HTTP fetches only to this origin;
 * - images from this origin, data: (the empty favicon) and blob:; no plugins, no <base>, forms
 *   post only here, and no page may frame this one.
 * The benchmark page (bench.html) alone also allows 'unsafe-eval': one of the peer engines it
 * compares (box2d3-wasm, an Emscripten build) makes its glue code with `new Function`. That page
 * takes no key and shows no player data; the sandbox and replay pages never get it.
 */

/** The Content-Security-Policy of every answer (see the file comment). */
export const CONTENT_SECURITY_POLICY = [
  "default-src 'self'",
  "script-src 'self' 'wasm-unsafe-eval'",
  "style-src 'self' 'unsafe-inline'",
  "img-src 'self' data: blob:",
  "connect-src 'self' ws: wss:",
  "object-src 'none'",
  "base-uri 'none'",
  "form-action 'self'",
  "frame-ancestors 'none'",
].join('; ')

/** Headers every HTTP answer carries (lower-case names, as Node writes them). */
export const SECURITY_HEADERS: Readonly<Record<string, string>> = {
  'content-security-policy': CONTENT_SECURITY_POLICY,
  'x-content-type-options': 'nosniff',
  'x-frame-options': 'DENY',
  'referrer-policy': 'no-referrer',
}

/** The static file whose page runs the peer engines (see the file comment). */
export const BENCH_PAGE = 'bench.html'

/** SECURITY_HEADERS for the benchmark page: its policy also allows 'unsafe-eval'. */
export const BENCH_SECURITY_HEADERS: Readonly<Record<string, string>> = {
  ...SECURITY_HEADERS,
  'content-security-policy': CONTENT_SECURITY_POLICY.replace(
    "script-src 'self' 'wasm-unsafe-eval'",
    "script-src 'self' 'wasm-unsafe-eval' 'unsafe-eval'",
  ),
}
