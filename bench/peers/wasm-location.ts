/*
 * Where a browser finds the .wasm files of the WebAssembly peers (box2d-wasm, box2d3-wasm). In
 * Node the peers read them from node_modules; a page that bundles the peers copies the files next
 * to itself and says where, relative to the page, so the build works under any base path.
 */

/** Maps a wasm file name (e.g. 'Box2D.simd.wasm') to the URL to fetch it from. */
export type WasmLocator = (file: string) => string

let locator: WasmLocator | null = null

/** Sets where the browser fetches wasm files (call before the first wasm peer is created). */
export function setWasmLocator(locate: WasmLocator): void {
  locator = locate
}

/** The locator the page set, or null (Node, or the package's own default). */
export function wasmLocator(): WasmLocator | null {
  return locator
}

/** Whether this code runs in Node (rather than a browser). */
export function inNode(): boolean {
  return typeof process !== 'undefined' && typeof process.versions?.node === 'string'
}
