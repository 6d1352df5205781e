/*
 * Contact and sensor events (Box2D v3's b2ContactEvents, b2SensorEvents): filled by step(), read
 * after it, valid until the next step. No user code runs inside step(): the events are plain
 * records the caller reads.
 *
 * Records live in pools that only grow, so a warm step allocates nothing: a step writes into the
 * pooled records and counts them; contactEvents() and sensorEvents() hand out the same object and
 * the same arrays every time (a shared frozen empty array when a list is empty), holding the records. Every list is in a deterministic order: by shape ids
 * (shapeA, then shapeB; sensor, then visitor).
 */
import type { Vec2 } from '../math.ts'
import type { ShapeId } from '../types.ts'

/** Two shapes began or stopped touching (shapeA < shapeB). */
export interface ContactTouchEvent {
  shapeA: ShapeId
  shapeB: ShapeId
}

/** Two shapes met faster than the hit threshold (1 m/s). */
export interface ContactHitEvent {
  shapeA: ShapeId
  shapeB: ShapeId
  /** World point of the fastest-closing manifold point (m). */
  point: Vec2
  /** World unit normal from shape A to shape B. */
  normal: Vec2
  /** Speed at which the shapes closed along the normal at the start of the step (m/s), > 0. */
  approachSpeed: number
}

/** A shape began or stopped overlapping a sensor. */
export interface SensorEvent {
  sensor: ShapeId
  visitor: ShapeId
}

/** What contactEvents() returns: the same object and arrays every call. */
export interface ContactEvents {
  begin: ContactTouchEvent[]
  end: ContactTouchEvent[]
  hit: ContactHitEvent[]
}

/** What sensorEvents() returns: the same object and arrays every call. */
export interface SensorEvents {
  begin: SensorEvent[]
  end: SensorEvent[]
}

/** A pool of records of one kind and the number in use. */
class Pool<T> {
  readonly items: T[] = []
  count = 0
  constructor(private readonly make: () => T) {}

  /** The next record (a fresh one only while the pool grows). */
  next(): T {
    if (this.count === this.items.length) this.items.push(this.make())
    return this.items[this.count++]
  }
}

/** The list handed out when there are no events (frozen; shared). */
const NONE: never[] = Object.freeze([]) as unknown as never[]

/**
 * The pool's first `count` records in `out` (the same array every time), or NONE when there are
 * none: V8 drops an array's storage when its length is set to 0 and allocates it again on the next
 * write, so the reused array is never emptied (a shorter length keeps the storage unless it falls
 * below half of it).
 */
function publish<T>(pool: Pool<T>, out: T[]): T[] {
  const n = pool.count
  if (n === 0) return NONE
  for (let i = 0; i < n; i++) out[i] = pool.items[i]
  out.length = n
  return out
}

/** Sorts the first `count` pair records by (a, b) in place: insertion sort, lists are short and nearly sorted. */
function sortPairs<T>(items: T[], count: number, a: (t: T) => number, b: (t: T) => number): void {
  for (let i = 1; i < count; i++) {
    const item = items[i]
    const ka = a(item)
    const kb = b(item)
    let j = i - 1
    while (j >= 0 && (a(items[j]) > ka || (a(items[j]) === ka && b(items[j]) > kb))) {
      items[j + 1] = items[j]
      j--
    }
    items[j + 1] = item
  }
}

const touchA = (e: ContactTouchEvent): number => e.shapeA
const touchB = (e: ContactTouchEvent): number => e.shapeB
const sensorA = (e: SensorEvent): number => e.sensor
const sensorB = (e: SensorEvent): number => e.visitor

/** The world's event buffers. */
export class EventBuffers {
  readonly begin = new Pool<ContactTouchEvent>(() => ({ shapeA: 0, shapeB: 0 }))
  readonly end = new Pool<ContactTouchEvent>(() => ({ shapeA: 0, shapeB: 0 }))
  /** Ends of contacts destroyed between steps (a destroyed shape, a changed filter), for the next step. */
  readonly pendingEnd = new Pool<ContactTouchEvent>(() => ({ shapeA: 0, shapeB: 0 }))
  readonly hit = new Pool<ContactHitEvent>(() => ({
    shapeA: 0,
    shapeB: 0,
    point: { x: 0, y: 0 },
    normal: { x: 0, y: 0 },
    approachSpeed: 0,
  }))
  readonly sensorBegin = new Pool<SensorEvent>(() => ({ sensor: 0, visitor: 0 }))
  readonly sensorEnd = new Pool<SensorEvent>(() => ({ sensor: 0, visitor: 0 }))
  private readonly contactView: ContactEvents = { begin: [], end: [], hit: [] }
  private readonly sensorView: SensorEvents = { begin: [], end: [] }
  /** The reused arrays behind the views. */
  private readonly lists = {
    begin: [] as ContactTouchEvent[],
    end: [] as ContactTouchEvent[],
    hit: [] as ContactHitEvent[],
    sensorBegin: [] as SensorEvent[],
    sensorEnd: [] as SensorEvent[],
  }

  /** Starts a step's events: clears the lists and moves the pending ends in. */
  beginStep(): void {
    this.begin.count = 0
    this.end.count = 0
    this.hit.count = 0
    this.sensorBegin.count = 0
    this.sensorEnd.count = 0
    const pending = this.pendingEnd
    for (let i = 0; i < pending.count; i++)
      this.addEnd(this.end, pending.items[i].shapeA, pending.items[i].shapeB)
    pending.count = 0
  }

  /** Records a touch event (begin, end or pending end) of shapes a < b. */
  addEnd(pool: Pool<ContactTouchEvent>, a: number, b: number): void {
    const e = pool.next()
    e.shapeA = a
    e.shapeB = b
  }

  /** Puts the step's lists in shape-id order (contacts are visited in that order; pending ends are not). */
  finishStep(): void {
    sortPairs(this.end.items, this.end.count, touchA, touchB)
    sortPairs(this.hit.items, this.hit.count, touchA, touchB)
    sortPairs(this.sensorBegin.items, this.sensorBegin.count, sensorA, sensorB)
    sortPairs(this.sensorEnd.items, this.sensorEnd.count, sensorA, sensorB)
  }

  /** The last step's contact events. */
  contactEvents(): ContactEvents {
    const v = this.contactView
    const l = this.lists
    v.begin = publish(this.begin, l.begin)
    v.end = publish(this.end, l.end)
    v.hit = publish(this.hit, l.hit)
    return v
  }

  /** The last step's sensor events. */
  sensorEvents(): SensorEvents {
    const v = this.sensorView
    const l = this.lists
    v.begin = publish(this.sensorBegin, l.sensorBegin)
    v.end = publish(this.sensorEnd, l.sensorEnd)
    return v
  }
}
