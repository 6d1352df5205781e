/*
 * Request targets from the network are untrusted text. `new URL(req.url, base)` throws on targets
 * such as `//%` or `//[` (read as a scheme-relative URL with a bad host), and one throw in a
 * request or upgrade handler would end the process. Every handler parses its target here: only
 * origin-form targets are accepted (RFC 9112 3.2.1: a path of RFC 3986 characters starting with
 * one "/", well-formed %-escapes, then an optional query of printable characters), parsed against
 * a fixed origin so the target can never name a host; anything else is null, answered with 400.
 */

/** The fixed origin request paths are resolved against (never contacted). */
const BASE = 'http://localhost'

/** Longest request target accepted (bytes of text); Node's own header limit is 16 KiB. */
export const MAX_TARGET_LENGTH = 8192

/** An absolute path of RFC 3986 path characters that does not start with "//". */
const PATH = /^\/(?!\/)[A-Za-z0-9\-._~!$&'()*+,;=:@/%]*$/
/** A "%" not followed by two hex digits. */
const BAD_ESCAPE = /%(?![0-9A-Fa-f]{2})/
/** Printable ASCII without space and "#" (a fragment never travels in a request). */
const QUERY = /^[\x21-\x22\x24-\x7e]*$/

/** A request target as a URL, or null when it is not a valid origin-form target. */
export function parseRequestTarget(target: string | undefined): URL | null {
  if (target === undefined || target.length === 0 || target.length > MAX_TARGET_LENGTH) return null
  const mark = target.indexOf('?')
  const path = mark < 0 ? target : target.slice(0, mark)
  const query = mark < 0 ? '' : target.slice(mark + 1)
  if (!PATH.test(path) || BAD_ESCAPE.test(path) || !QUERY.test(query)) return null
  try {
    // Concatenation, not `new URL(target, BASE)`: a target starting with "//" must stay a path.
    const url = new URL(BASE + target)
    return url.origin === BASE ? url : null
  } catch {
    return null
  }
}

/** A bare HTTP response for a raw socket (upgrade refusals, connection caps), closing it after. */
export function rawHttpResponse(status: number, text: string, headers: Record<string, string> = {}): string {
  const lines = [`HTTP/1.1 ${status} ${text}`, 'Connection: close', 'Content-Length: 0']
  for (const [name, value] of Object.entries(headers)) lines.push(`${name}: ${value}`)
  return `${lines.join('\r\n')}\r\n\r\n`
}
