/*
 * The notices a mode keeps for the page (Sandbox.notices): problems with this player's inputs,
 * counted, with the newest and the last few (oldest first), so that two in quick succession both
 * show. The online, lockstep and offline sandboxes keep theirs here.
 */

/** How many of the latest notices are kept for the page. */
const RECENT_NOTICES = 3

/** A mode's notices so far (see the file comment). */
export class NoticeLog {
  count = 0
  latest: string | null = null
  readonly recent: string[] = []

  /** Count a notice and keep it among the last few. */
  add(text: string): void {
    this.count++
    this.latest = text
    this.recent.push(text)
    if (this.recent.length > RECENT_NOTICES) this.recent.shift()
  }
}
