/*
 * How far behind a client is in reading, in bytes. ws's bufferedAmount only counts what the
 * server has not yet handed to the kernel, and on a real link the kernel's send and receive
 * buffers absorb megabytes first (on loopback about 6 MB), so a reader that reads slowly but
 * answers pings never showed up over the send-buffer budget: the slow-reader rule never fired,
 * and the heartbeat closed paused readers instead (issue 11, item 7).
 *
 * Acks tell the truth: when a client acknowledges the snapshot of tick T, it has read every byte
 * the server sent up to and including that snapshot. So the server remembers, for each snapshot
 * sent, the running total of bytes sent just after it; an ack moves the "read through" mark
 * there; unread bytes are everything sent since. A client that never acks (acks are part of the
 * protocol, but a minimal client might skip them) is measured by the unsent bytes alone.
 */

/** Snapshots remembered per client for acks (2 s at 60 snapshots a second). */
const MAX_MARKS = 120

/** The bytes a client has been sent but has not confirmed reading. */
export class UnreadBytes {
  /** Pairs (snapshot tick, total bytes sent after it), oldest first. */
  private readonly marks: number[] = []
  private readThrough = 0
  private acking = false

  /** The snapshot of `tick` was just sent, bringing the running total to `totalSent` bytes. */
  snapshotSent(tick: number, totalSent: number): void {
    this.marks.push(tick, totalSent)
    if (this.marks.length > 2 * MAX_MARKS) this.marks.splice(0, 2)
  }

  /** The client acknowledged the snapshot of `tick`; unknown or old ticks change nothing. */
  acknowledged(tick: number): void {
    const marks = this.marks
    let i = 0
    while (i < marks.length && marks[i] !== tick) i += 2
    if (i >= marks.length) return
    this.readThrough = Math.max(this.readThrough, marks[i + 1])
    this.acking = true
    marks.splice(0, i + 2)
  }

  /** Bytes not known to be read: unsent ones, or for an acking client all sent since its last ack. */
  unread(totalSent: number, unsent: number): number {
    return this.acking ? Math.max(unsent, totalSent - this.readThrough) : unsent
  }
}
