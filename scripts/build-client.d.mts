/** Bundle the browser client into `outdir` (default dist/client); returns the sizes of app.js. */
export function buildClient(
  outdir?: string,
): Promise<{ bytes: number; gzipBytes: number; htmlGzipBytes: number }>
