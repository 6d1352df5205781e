/*
 * Scripted player activity for the lockstep tests: spawns, grabs and drags, releases, pins, ropes,
 * unjoints and deletes, chosen by a seeded PRNG from the bodies the player can see. The same
 * script drives in-process simulations and bots over real sockets.
 */
import { Prng } from '../../engine/index.ts'
import type { Command } from '../../shared/index.ts'

/** What the script needs to know: the dynamic bodies and the user joints as the player sees them. */
export interface ActivityView {
  dynamicBodies(): number[]
  userJoints(): number[]
}

/** One player's scripted activity; call next() once per action slot. */
export class Activity {
  private readonly prng: Prng
  private step = 0

  /** `quiet` makes a player that does nothing (for the end of a test). */
  constructor(
    seed: number,
    private readonly mode: 'busy' | 'quiet' = 'busy',
  ) {
    this.prng = new Prng(seed)
  }

  /** The next command (or null for a quiet slot). */
  next(view: ActivityView): Command | null {
    if (this.mode === 'quiet') return null
    const p = this.prng
    const step = this.step++
    const bodies = view.dynamicBodies()
    const pick = (): number => bodies[p.int(bodies.length)]
    if (step % 40 === 0 || bodies.length < 3) {
      const kind = p.int(3)
      const shape =
        kind === 0
          ? { type: 'circle' as const, radius: 0.2 + p.next() * 0.3 }
          : kind === 1
            ? { type: 'box' as const, hw: 0.2 + p.next() * 0.3, hh: 0.2 + p.next() * 0.3 }
            : { type: 'polygon' as const, v: [-0.4, -0.3, 0.4, -0.3, 0, 0.5] }
      return { k: 'spawn', shape, x: p.next() * 16 - 8, y: 6 + p.next() * 6, vx: p.next() - 0.5 }
    }
    const phase = step % 40
    if (phase === 1) return { k: 'grab', body: pick(), lx: p.next() * 0.2, ly: 0 }
    if (phase < 25) {
      const a = phase * 0.3 + p.next() * 0.1
      return { k: 'move', x: 3 * Math.cos(a), y: 5 + 2 * Math.sin(a) }
    }
    if (phase === 25) return { k: 'release' }
    if (phase === 27) return { k: 'pin', a: 0, b: pick(), x: p.next() * 10 - 5, y: 3 + p.next() * 3 }
    if (phase === 29) {
      const a = pick()
      const b = pick()
      return a === b ? null : { k: 'rope', a, b, ax: -1, ay: 4, bx: 1, by: 4 }
    }
    if (phase === 33) {
      const joints = view.userJoints()
      return joints.length > 0 ? { k: 'unjoint', joint: joints[p.int(joints.length)] } : null
    }
    if (phase === 36 && bodies.length > 8) return { k: 'delete', body: pick() }
    return null
  }
}
