/*
 * Streaming reader of replay logs (format: replay-log.ts, docs/replay-format.md). push() takes
 * bytes as they arrive (a whole file, or fetch/stream chunks) and returns the records completed
 * by them. It never returns a record that fails its length bound, CRC-32, decoding or ordering
 * checks (ticks never go back, nor jump more than MAX_RECORD_GAP ahead): at the first such record
 * it stops for good and says why; bytes after it are ignored. finish() tells a clean end from a
 * torn tail (an incomplete last record). A block record's records come out one by one, all with
 * the byte offset of the block's end; a block is accepted whole or not at all.
 */
import { crc32 } from './crc32.ts'
import {
  decodePreamble,
  decodeRecordBody,
  MAX_RECORD_BYTES,
  MAX_RECORD_GAP,
  PREAMBLE_BYTES,
  type Preamble,
  ReplayFormatError,
  type ReplayRecord,
} from './replay-log.ts'

/** Where reading stands. */
export interface ReadStatus {
  /** 'reading' while more may come; 'end' at a record boundary; 'torn' mid-record; 'corrupt' at a bad record; 'invalid' for a bad preamble or header. */
  state: 'reading' | 'end' | 'torn' | 'corrupt' | 'invalid'
  /** Why reading stopped (empty while reading or at a clean end). */
  reason: string
  /** Records accepted. */
  records: number
  /** Bytes of the intact prefix (preamble and accepted records). */
  intactBytes: number
  /** Tick of the header and of the last accepted record (-1 before the header). */
  firstTick: number
  lastTick: number
  /** Whether the last accepted record is a clean close. */
  closed: boolean
}

/** A streaming, never-trusting log reader (see the file comment). */
export class ReplayLogReader {
  preamble: Preamble | null = null
  private buffer = new Uint8Array(0)
  private offset = 0
  private readonly status: ReadStatus = {
    state: 'reading',
    reason: '',
    records: 0,
    intactBytes: 0,
    firstTick: -1,
    lastTick: -1,
    closed: false,
  }

  /**
   * Feed more bytes; returns the records they complete (none once reading has stopped). `each`
   * sees every record with the byte offset just past it.
   */
  push(chunk: Uint8Array, each?: (record: ReplayRecord, end: number) => void): ReplayRecord[] {
    const out: ReplayRecord[] = []
    if (this.stopped) return out
    this.append(chunk)
    if (!this.preamble) {
      if (this.buffer.length - this.offset < PREAMBLE_BYTES) return out
      try {
        this.preamble = decodePreamble(this.buffer.subarray(this.offset, this.offset + PREAMBLE_BYTES))
      } catch (error) {
        this.stop('invalid', (error as Error).message)
        return out
      }
      this.offset += PREAMBLE_BYTES
      this.status.intactBytes = PREAMBLE_BYTES
    }
    for (;;) {
      const records = this.next()
      if (!records) break
      for (const r of records) {
        out.push(r)
        each?.(r, this.status.intactBytes)
      }
    }
    this.compact()
    return out
  }

  /** The stream ended: the final status (torn when bytes of an incomplete record are left). */
  finish(): ReadStatus {
    const final = this.finalStatus()
    if (this.status.state === 'reading') {
      if (final.state === 'end') this.status.state = 'end'
      else this.stop(final.state, final.reason)
    }
    return { ...this.status }
  }

  /**
   * What finish() would report if the bytes ended here, without ending the read: a reader of a
   * log that is still being written can go on with the bytes appended later.
   */
  finalStatus(): ReadStatus {
    const status = { ...this.status }
    if (status.state !== 'reading') return status
    const end = (state: ReadStatus['state'], reason: string): ReadStatus => ({ ...status, state, reason })
    if (!this.preamble) return end('invalid', `too short for a replay log (${this.buffer.length} bytes)`)
    if (status.records === 0) return end('invalid', 'the log has no header record')
    if (this.buffer.length > this.offset)
      return end('torn', `torn tail: ${this.buffer.length - this.offset} bytes of an incomplete record`)
    return { ...status, state: 'end' }
  }

  /** The current status. */
  get current(): ReadStatus {
    return { ...this.status }
  }

  private get stopped(): boolean {
    return this.status.state !== 'reading'
  }

  private stop(state: ReadStatus['state'], reason: string): void {
    this.status.state = state
    this.status.reason = reason
    this.buffer = new Uint8Array(0)
    this.offset = 0
  }

  private append(chunk: Uint8Array): void {
    if (chunk.length === 0) return
    const left = this.buffer.length - this.offset
    const grown = new Uint8Array(left + chunk.length)
    grown.set(this.buffer.subarray(this.offset))
    grown.set(chunk, left)
    this.buffer = grown
    this.offset = 0
  }

  private compact(): void {
    if (this.offset > 0 && this.offset === this.buffer.length) {
      this.buffer = new Uint8Array(0)
      this.offset = 0
    }
  }

  private next(): ReplayRecord[] | null {
    const available = this.buffer.length - this.offset
    if (available < 4) return null
    const view = new DataView(this.buffer.buffer, this.buffer.byteOffset + this.offset, available)
    const length = view.getUint32(0, true)
    const at = `record ${this.status.records + 1} at byte ${this.status.intactBytes}`
    if (length < 5 || length > MAX_RECORD_BYTES) {
      this.stop('corrupt', `${at}: impossible length ${length}`)
      return null
    }
    if (available < 4 + length + 4) return null
    const end = this.offset + 4 + length
    const stored = view.getUint32(4 + length, true)
    if (crc32(this.buffer, this.offset, end) !== stored) {
      this.stop('corrupt', `${at}: checksum mismatch`)
      return null
    }
    let records: ReplayRecord[]
    try {
      records = decodeRecordBody(this.buffer.subarray(this.offset + 4, end), this.preamble?.format)
    } catch (error) {
      const reason = error instanceof ReplayFormatError ? error.message : String(error)
      this.stop('corrupt', `${at}: ${reason}`)
      return null
    }
    const problem = this.order(records)
    if (problem) {
      this.stop(this.status.records === 0 ? 'invalid' : 'corrupt', `${at}: ${problem}`)
      return null
    }
    this.offset = end + 4
    this.status.records += records.length
    this.status.intactBytes += 4 + length + 4
    const last = records[records.length - 1]
    if (records[0].type === 'header') this.status.firstTick = records[0].tick
    this.status.lastTick = last.tick
    this.status.closed = last.type === 'close'
    return records
  }

  /** Why these records (one, or a block's) cannot come next, or null. */
  private order(records: ReplayRecord[]): string | null {
    let count = this.status.records
    let closed = this.status.closed
    let lastTick = this.status.lastTick
    for (const r of records) {
      if (count === 0 && r.type !== 'header') return 'the first record is not a header'
      if (count > 0 && r.type === 'header') return 'a second header'
      if (closed) return 'a record after the clean close'
      if (r.tick < lastTick) return `tick ${r.tick} goes back from ${lastTick}`
      if (count > 0 && r.tick - lastTick > MAX_RECORD_GAP)
        return `tick ${r.tick} is ${r.tick - lastTick} ticks after the record before it (at most ${MAX_RECORD_GAP})`
      count++
      closed = r.type === 'close'
      lastTick = r.tick
    }
    return null
  }
}
