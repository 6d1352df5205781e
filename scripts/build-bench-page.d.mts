/** Bundle the benchmark page into `outdir` (default dist/client); returns the size of bench.js. */
export function buildBenchPage(outdir?: string): Promise<{ bytes: number }>
