/*
 * Continuous collision. Every case is run twice: once as stated, and once with the one thing that
 * should matter switched off (continuous collision, or the bullet flag), to prove that the setup
 * really tunnels without it. Oracles: geometry (the bullet's centre may never pass the wall's near
 * face minus its radius, nor the plank or the other bullet), and conservation of momentum in the
 * impacts (no gravity, so total momentum is constant whatever the solver does).
 */
import { describe, expect, it } from 'vitest'
import { box, circle, createWorld, type Vec2, type World } from '../../engine/index.ts'

const SLOP = 0.005

interface Shot {
  world: World
  bullet: number
  target: number
}

/** A 300 m/s shot along +x from the origin at a body centred at x = 5. */
function shot(opts: {
  continuous: boolean
  bullet: boolean
  target: 'wall' | 'plank' | 'bullet'
  targetVelocity?: Vec2
}): Shot {
  const world = createWorld({ gravity: { x: 0, y: 0 }, enableContinuous: opts.continuous })
  let target: number
  if (opts.target === 'wall') {
    target = world.createBody({ type: 'static', position: { x: 5, y: 0 }, shape: box(0.025, 2) })
  } else if (opts.target === 'plank') {
    target = world.createBody({
      position: { x: 5, y: 0 },
      shape: box(0.025, 1),
      linearVelocity: opts.targetVelocity ?? { x: 0, y: 0 },
    })
  } else {
    target = world.createBody({
      position: { x: 5, y: 0 },
      shape: circle(0.05),
      bullet: true,
      linearVelocity: { x: -300, y: 0 },
    })
  }
  const bullet = world.createBody({
    position: { x: 0, y: 0 },
    shape: circle(0.05),
    linearVelocity: { x: 300, y: 0 },
    bullet: opts.bullet,
  })
  return { world, bullet, target }
}

function momentumX(w: World, ids: number[]): number {
  let p = 0
  for (const id of ids) p += w.getMass(id) * w.getLinearVelocity(id).x
  return p
}

/** Steps `n` times; returns the largest (bullet x - target x) seen after any step. */
function maxLead(s: Shot, n: number): number {
  let lead = Number.NEGATIVE_INFINITY
  for (let i = 0; i < n; i++) {
    s.world.step()
    lead = Math.max(lead, s.world.getPosition(s.bullet).x - s.world.getPosition(s.target).x)
  }
  return lead
}

describe('a 300 m/s bullet against a 5 cm static wall', () => {
  it('stops at the wall with continuous collision on (bullet flag or not)', () => {
    for (const bullet of [true, false]) {
      const s = shot({ continuous: true, bullet, target: 'wall' })
      const lead = maxLead(s, 60)
      // The near face is at x = 4.975; the bullet's centre may not pass 4.975 - 0.05.
      expect(lead).toBeLessThanOrEqual(-0.025 - 0.05 + SLOP)
      expect(s.world.getLinearVelocity(s.bullet).x).toBeCloseTo(0, 6)
    }
  })

  it('tunnels through the wall with continuous collision off (the setup is real)', () => {
    const s = shot({ continuous: false, bullet: true, target: 'wall' })
    expect(maxLead(s, 60)).toBeGreaterThan(10)
    expect(s.world.getLinearVelocity(s.bullet).x).toBe(300)
  })
})

describe('a 300 m/s bullet against a thin (5 cm) dynamic plank', () => {
  for (const plankSpeed of [0, -50, -200, 100]) {
    it(`is stopped by a plank moving at ${plankSpeed} m/s, conserving momentum`, () => {
      const s = shot({
        continuous: true,
        bullet: true,
        target: 'plank',
        targetVelocity: { x: plankSpeed, y: 0 },
      })
      const ids = [s.bullet, s.target]
      const p0 = momentumX(s.world, ids)
      expect(maxLead(s, 60)).toBeLessThanOrEqual(-0.075 + SLOP)
      expect(momentumX(s.world, ids)).toBeCloseTo(p0, 9)
      // Restitution 0: they end up moving together at the centre-of-mass velocity.
      const vCom = p0 / (s.world.getMass(s.bullet) + s.world.getMass(s.target))
      expect(s.world.getLinearVelocity(s.bullet).x).toBeCloseTo(vCom, 3)
      expect(s.world.getLinearVelocity(s.target).x).toBeCloseTo(vCom, 3)
    })
  }

  it('tunnels without the bullet flag (fast bodies are swept against static bodies only)', () => {
    const s = shot({ continuous: true, bullet: false, target: 'plank' })
    expect(maxLead(s, 60)).toBeGreaterThan(10)
  })

  it('is hit by a plank that crosses its path sideways from outside its swept box', () => {
    for (const bullet of [true, false]) {
      const world = createWorld({ gravity: { x: 0, y: 0 } })
      // At half the step the plank (y = 2 - 240 t) and the bullet (x = 300 t) meet at (2.5, 0).
      const plank = world.createBody({
        position: { x: 2.5, y: 2 },
        shape: box(0.5, 0.025),
        linearVelocity: { x: 0, y: -240 },
      })
      const b = world.createBody({
        position: { x: 0, y: 0 },
        shape: circle(0.05),
        linearVelocity: { x: 300, y: 0 },
        bullet,
      })
      world.step()
      const vy = world.getLinearVelocity(b).y
      world.step()
      const hit = world.getLinearVelocity(b).y < -100 && world.getLinearVelocity(plank).y > -239
      expect({ bullet, hit }).toEqual({ bullet, hit: bullet })
      if (!bullet) expect(vy).toBe(0)
    }
  })
})

describe('two 300 m/s bullets head-on', () => {
  it('collide instead of passing through each other, conserving momentum', () => {
    const s = shot({ continuous: true, bullet: true, target: 'bullet' })
    const ids = [s.bullet, s.target]
    expect(momentumX(s.world, ids)).toBe(0)
    let minGap = Number.POSITIVE_INFINITY
    for (let i = 0; i < 60; i++) {
      s.world.step()
      const gap = s.world.getPosition(s.target).x - s.world.getPosition(s.bullet).x - 0.1
      minGap = Math.min(minGap, gap)
    }
    expect(minGap).toBeGreaterThan(-SLOP)
    expect(Math.abs(momentumX(s.world, ids))).toBeLessThan(1e-12)
    expect(Math.abs(s.world.getLinearVelocity(s.bullet).x)).toBeLessThan(1e-6)
  })

  it('pass through each other with continuous collision off', () => {
    const s = shot({ continuous: false, bullet: true, target: 'bullet' })
    expect(maxLead(s, 60)).toBeGreaterThan(10)
  })
})

describe('sweeps with rotation', () => {
  // Spinning 1 m x 4 cm bars thrown at a tall wall: the sweep covers the rotation (conservative
  // advancement bounds the rotating surface's speed). The last three hit with a tip and are spun
  // up to the angular speed cap (pi/4 per sub-step), faster than the contact can follow: the bar
  // turns through the wall in the next step, and only the core sweep (its centre may never cross)
  // with the removal of the centre's velocity into the wall stops it.
  for (const [speed, spin] of [
    [300, 20],
    [100, 10],
    [50, 30],
    [150, 15],
    [200, 40],
    [100, 40],
  ]) {
    it(`a thin bar at ${speed} m/s spinning at ${spin} rad/s does not pass a static wall`, () => {
      for (const continuous of [true, false]) {
        const world = createWorld({ gravity: { x: 0, y: 0 }, enableContinuous: continuous })
        world.createBody({ type: 'static', position: { x: 5, y: 0 }, shape: box(0.025, 100) })
        const bar = world.createBody({
          position: { x: 0, y: 0 },
          shape: box(0.5, 0.02),
          linearVelocity: { x: speed, y: 0 },
          angularVelocity: spin,
        })
        let maxX = Number.NEGATIVE_INFINITY
        for (let i = 0; i < 60; i++) {
          world.step()
          maxX = Math.max(maxX, world.getPosition(bar).x)
        }
        if (continuous) expect(maxX).toBeLessThan(4.975)
        else expect(maxX).toBeGreaterThan(10)
      }
    })
  }
})
