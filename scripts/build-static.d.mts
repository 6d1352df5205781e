/** The marker client/main.ts looks for. */
export const OFFLINE_META: string
/** Build the static site into `outdir` (emptied first); returns the sizes of the two bundles. */
export function buildStatic(outdir?: string): Promise<{ appBytes: number; benchBytes: number }>
