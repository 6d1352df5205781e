/*
 * Waiting on a condition, the one way tests (and the load benchmarks) wait: poll until it holds,
 * fail naming what was awaited when it does not within the time allowed. Never a fixed sleep.
 */

/** Resolves once `condition` holds (polled every `pollMs`); throws "timed out waiting for WHAT" after `timeoutMs`. */
export async function until(
  condition: () => boolean | Promise<boolean>,
  what: string,
  timeoutMs = 30_000,
  pollMs = 25,
): Promise<void> {
  const deadline = Date.now() + timeoutMs
  while (!(await condition())) {
    if (Date.now() > deadline) throw new Error(`timed out waiting for ${what}`)
    await new Promise((resolve) => setTimeout(resolve, pollMs))
  }
}
