/** Build the client SDK into `outdir` (default dist/sdk); returns the entry files written. */
export function buildSdk(outdir?: string): Promise<string[]>
