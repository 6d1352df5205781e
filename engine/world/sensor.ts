/*
 * Sensors (Box2D v3.1's sensor.c): a sensor shape makes no contacts and never pushes; at the end of
 * each step it finds the shapes that overlap it, and the differences from the last step are the
 * sensor events (begin, end).
 *
 * Per sensor, in shape-id order: the broadphase gives the shapes whose fat boxes touch the sensor's
 * box (sorted by id); a candidate counts if it is on another body, is not a sensor, has
 * enableSensorEvents, passes the filter rule with the sensor, and truly overlaps it (the narrowphase
 * at zero speculative distance finds a point of negative separation). The visitors are kept sorted,
 * so comparing with last step's list is one merge. Nothing allocates once the lists have grown.
 */

import { type BroadPhase, collideGeometryAt, IdBuffer, Manifold } from '../collision/index.ts'
import { type BodyShape, shouldFilterCollide } from '../dynamics/index.ts'
import type { EventBuffers } from './events.ts'

/** A sensor shape and the ids of the shapes overlapping it after the last step (ascending). */
export class SensorState {
  visitors: number[] = []
  count = 0
  /** Scratch for the next list (swapped with `visitors`). */
  next: number[] = []
  constructor(readonly shape: BodyShape) {}
}

const candidates = new IdBuffer()
const manifold = new Manifold()

/** Whether shape o overlaps sensor s (exact, at the current poses, zero speculative distance). */
function overlaps(s: BodyShape, o: BodyShape): boolean {
  collideGeometryAt(s.shape, s.geometry, s.body, o.shape, o.geometry, o.body, manifold)
  return manifold.pointCount > 0
}

/**
 * Updates every sensor's visitors and records the begin and end events. `box` is a 4-number scratch
 * the caller fills with a shape's tight AABB through `computeBox`.
 */
export function updateSensors(
  sensors: SensorState[],
  broadPhase: BroadPhase,
  shapes: Map<number, BodyShape>,
  events: EventBuffers,
  box: Float64Array,
  computeBox: (s: BodyShape) => void,
): void {
  for (let i = 0; i < sensors.length; i++) {
    const state = sensors[i]
    const sensor = state.shape
    computeBox(sensor)
    const n = broadPhase.queryBox(box, candidates)
    const next = state.next
    let count = 0
    for (let k = 0; k < n; k++) {
      const o = shapes.get(candidates.ids[k])
      if (o === undefined || o.body === sensor.body || o.sensor || !o.enableSensorEvents) continue
      if (!shouldFilterCollide(sensor, o) || !overlaps(sensor, o)) continue
      next[count++] = o.id
    }
    // Merge with last step's list: ids only in `next` began, ids only in `visitors` ended.
    const prev = state.visitors
    const prevCount = state.count
    let p = 0
    let q = 0
    while (p < prevCount || q < count) {
      const a = p < prevCount ? prev[p] : Number.POSITIVE_INFINITY
      const b = q < count ? next[q] : Number.POSITIVE_INFINITY
      if (a === b) {
        p++
        q++
      } else if (a < b) {
        const e = events.sensorEnd.next()
        e.sensor = sensor.id
        e.visitor = a
        p++
      } else {
        const e = events.sensorBegin.next()
        e.sensor = sensor.id
        e.visitor = b
        q++
      }
    }
    state.next = prev
    state.visitors = next
    state.count = count
  }
}
