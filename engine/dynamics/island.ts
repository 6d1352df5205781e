/*
 * Islands and sleep.
 *
 * An island is a set of non-static bodies connected by touching contacts and joints. Islands are
 * rebuilt every step with union-find over the awake bodies (in id order, so the result does not
 * depend on memory or timing), which costs a pass over the awake bodies, contacts and joints and
 * keeps no persistent island state to save or corrupt. An island falls asleep when every body in
 * it has rested (sleep velocity below the threshold) for `timeToSleep`; a sleeping island costs
 * nothing per step. Waking is a flood fill from the touched body through touching contacts and
 * joints, so a whole sleeping island always wakes together (Box2D's rule: sleep is per island,
 * never per body).
 */

import type { Joint } from '../joints/index.ts'
import { type Body, STATIC } from './body.ts'
import type { Contact } from './contact.ts'

/** Union-find state reused across steps. */
export class IslandBuilder {
  private parent = new Int32Array(64)
  private minSleep = new Float64Array(64)
  private readonly stack: Body[] = []

  private find(i: number): number {
    const parent = this.parent
    let root = i
    while (parent[root] !== root) root = parent[root]
    while (parent[i] !== root) {
      const next = parent[i]
      parent[i] = root
      i = next
    }
    return root
  }

  private union(a: Body, b: Body): void {
    if (a.solverIndex < 0 || b.solverIndex < 0) return
    const ra = this.find(a.solverIndex)
    const rb = this.find(b.solverIndex)
    // The smaller slot (earlier id) becomes the root: deterministic.
    if (ra < rb) this.parent[rb] = ra
    else if (rb < ra) this.parent[ra] = rb
  }

  /**
   * Puts to sleep every island of awake bodies whose slowest-to-rest member has rested for
   * `timeToSleep` (s). `awake` is in id order and each body's solverIndex is its slot.
   */
  sleepIslands(
    awake: Body[],
    awakeCount: number,
    contacts: Contact[],
    contactCount: number,
    joints: Joint[],
    jointCount: number,
    timeToSleep: number,
  ): void {
    if (this.parent.length < awakeCount) {
      this.parent = new Int32Array(awakeCount * 2)
      this.minSleep = new Float64Array(awakeCount * 2)
    }
    const parent = this.parent
    for (let i = 0; i < awakeCount; i++) parent[i] = i
    for (let i = 0; i < contactCount; i++) {
      const c = contacts[i]
      if (c.touching && c.bodyA.type !== STATIC && c.bodyB.type !== STATIC) this.union(c.bodyA, c.bodyB)
    }
    for (let i = 0; i < jointCount; i++) {
      const j = joints[i]
      if (j.bodyA.type !== STATIC && j.bodyB.type !== STATIC) this.union(j.bodyA, j.bodyB)
    }
    const minSleep = this.minSleep
    for (let i = 0; i < awakeCount; i++) minSleep[i] = Number.POSITIVE_INFINITY
    for (let i = 0; i < awakeCount; i++) {
      const root = this.find(i)
      const t = awake[i].sleepTime
      if (t < minSleep[root]) minSleep[root] = t
    }
    for (let i = 0; i < awakeCount; i++) {
      if (minSleep[this.find(i)] >= timeToSleep) putToSleep(awake[i])
    }
  }

  /** Wakes a body and, by flood fill through touching contacts and joints, its whole island. */
  wake(body: Body): void {
    if (body.type === STATIC || body.awake) return
    const stack = this.stack
    stack.push(body)
    while (stack.length > 0) {
      const b = stack.pop()!
      if (b.awake) continue
      b.awake = true
      b.sleepTime = 0
      for (let i = 0; i < b.contacts.length; i++) {
        const c = b.contacts[i]
        if (!c.touching) continue
        const other = c.bodyA === b ? c.bodyB : c.bodyA
        if (other.type !== STATIC && !other.awake) stack.push(other)
      }
      for (let i = 0; i < b.joints.length; i++) {
        const other = b.joints[i].other(b)
        if (other.type !== STATIC && !other.awake) stack.push(other)
      }
    }
  }

  /** Puts a body's whole island (through touching contacts and joints) to sleep at once. */
  sleep(body: Body): void {
    if (body.type === STATIC || !body.awake) return
    const stack = this.stack
    stack.push(body)
    while (stack.length > 0) {
      const b = stack.pop()!
      if (!b.awake) continue
      putToSleep(b)
      for (let i = 0; i < b.contacts.length; i++) {
        const c = b.contacts[i]
        if (!c.touching) continue
        const other = c.bodyA === b ? c.bodyB : c.bodyA
        if (other.type !== STATIC && other.awake) stack.push(other)
      }
      for (let i = 0; i < b.joints.length; i++) {
        const other = b.joints[i].other(b)
        if (other.type !== STATIC && other.awake) stack.push(other)
      }
    }
  }
}

function putToSleep(body: Body): void {
  body.awake = false
  body.vx = 0
  body.vy = 0
  body.w = 0
}
