/*
 * Robustness of the new joint kinds (issue 28), reported as numbers:
 * - a 30-link weld chain held horizontally from a wall with a tip load 10 times a link's mass:
 *   the welds' anchors stay together and the chain keeps its shape (tip sag);
 * - a 10-wheel train (one 10 m chassis on ten sprung wheel joints with motors) carrying 20 boxes
 *   drives over bumps: every wheel stays on its axis (across-axis error) and within its travel;
 * - hostile settings on every new kind (1e6 Hz springs, 1e12 N motors, anchors 500 m away, a motor
 *   joint's offset 1e5 m away, zero-length axes refused) keep every body finite and within the
 *   speed limits.
 */
import { describe, expect, it } from 'vitest'
import { box, circle, createWorld, type World } from '../../engine/index.ts'

/** Largest distance between any joint's two anchors (m), over the joints whose anchors should coincide. */
function worstGap(world: World, types: string[]): number {
  let worst = 0
  for (const j of world.joints()) {
    if (!types.includes(j.type)) continue
    worst = Math.max(worst, Math.hypot(j.anchorA.x - j.anchorB.x, j.anchorA.y - j.anchorB.y))
  }
  return worst
}

describe('new joints: robustness', () => {
  it('a 30-link weld chain held horizontally with a 10:1 tip load keeps its shape', () => {
    const world = createWorld({ enableSleep: false })
    const wall = world.createBody({ type: 'static', position: { x: -0.5, y: 10 }, shape: box(0.5, 1) })
    let previous = wall
    const links: number[] = []
    for (let i = 0; i < 30; i++) {
      const link = world.createBody({ position: { x: 0.25 + 0.5 * i, y: 10 }, shape: box(0.25, 0.05) })
      world.createJoint({ type: 'weld', bodyA: previous, bodyB: link, anchor: { x: 0.5 * i, y: 10 } })
      links.push(link)
      previous = link
    }
    // Tip load: 10 link masses (a link is 0.05 kg), a 0.2 m box welded at the chain's end.
    const load = world.createBody({ position: { x: 15.1, y: 10 }, shape: box(0.1, 0.1), density: 12.5 })
    world.createJoint({ type: 'weld', bodyA: previous, bodyB: load, anchor: { x: 15, y: 10 } })
    expect(world.getMass(load)).toBeCloseTo(10 * world.getMass(links[0]), 9)
    let gap = 0
    let sag = 0
    for (let i = 0; i < 600; i++) {
      world.step()
      gap = Math.max(gap, worstGap(world, ['weld']))
      sag = Math.max(sag, 10 - world.getPosition(load).y)
    }
    const speed = Math.hypot(world.getLinearVelocity(load).x, world.getLinearVelocity(load).y)
    console.log(
      `30-link weld cantilever, 10:1 tip load, 10 s: tip sag at most ${(sag * 1000).toFixed(3)} mm, anchors apart at most ${(gap * 1000).toFixed(4)} mm, tip speed ${speed.toExponential(2)} m/s`,
    )
    expect(sag).toBeLessThan(0.05)
    expect(gap).toBeLessThan(0.001)
    expect(speed).toBeLessThan(0.01)
  })

  it('a 10-wheel train carrying 20 boxes over bumps keeps every wheel on its axis and within its travel', () => {
    const world = createWorld({ enableSleep: false })
    world.createBody({ type: 'static', position: { x: 0, y: -0.5 }, shape: box(200, 0.5), friction: 0.9 })
    for (let i = 0; i < 12; i++)
      world.createBody({
        type: 'static',
        position: { x: 10 + 3 * i, y: 0 },
        angle: Math.PI / 4,
        shape: box(0.1, 0.1),
      })
    const chassis = world.createBody({ position: { x: 0, y: 1.2 }, shape: box(5, 0.2), density: 2 })
    const joints: number[] = []
    for (let i = 0; i < 10; i++) {
      const at = { x: -4.5 + i, y: 0.35 }
      const wheel = world.createBody({ position: at, shape: circle(0.35), friction: 0.9 })
      joints.push(
        world.createJoint({
          type: 'wheel',
          bodyA: chassis,
          bodyB: wheel,
          anchor: at,
          axis: { x: 0, y: 1 },
          hertz: 5,
          dampingRatio: 0.7,
          enableLimit: true,
          lower: -0.2,
          upper: 0.2,
          enableMotor: true,
          motorSpeed: -8,
          maxMotorTorque: 30,
        }),
      )
    }
    for (let i = 0; i < 20; i++)
      world.createBody({ position: { x: -4.6 + 0.48 * i, y: 1.65 }, shape: box(0.22, 0.22), density: 3 })
    let across = 0
    let low = 0
    let high = 0
    for (let s = 0; s < 600; s++) {
      world.step()
      const a = world.getAngle(chassis)
      const up = { x: -Math.sin(a), y: Math.cos(a) }
      for (const j of joints) {
        const info = world.joints().find((x) => x.id === j)
        if (!info) throw new Error('wheel joint missing')
        const dx = info.anchorB.x - info.anchorA.x
        const dy = info.anchorB.y - info.anchorA.y
        across = Math.max(across, Math.abs(dx * up.y - dy * up.x))
        const t = world.getJointTranslation(j)
        low = Math.min(low, t)
        high = Math.max(high, t)
      }
    }
    const x = world.getPosition(chassis).x
    console.log(
      `10-wheel train, 20 boxes, 10 s: drove ${x.toFixed(2)} m, wheels off their axis at most ${(across * 1000).toFixed(3)} mm, travel ${(low * 1000).toFixed(1)} to ${(high * 1000).toFixed(1)} mm (limits +-200)`,
    )
    expect(x).toBeGreaterThan(15)
    expect(across).toBeLessThan(0.005)
    expect(low).toBeGreaterThan(-0.2 - 0.005)
    expect(high).toBeLessThan(0.2 + 0.005)
  })

  it('hostile settings on every new kind keep every body finite and within the speed limits', () => {
    const world = createWorld({ enableSleep: false })
    world.createBody({ type: 'static', position: { x: 0, y: -1 }, shape: box(50, 1) })
    const bodies: number[] = []
    for (let i = 0; i < 8; i++)
      bodies.push(world.createBody({ position: { x: -7 + 2 * i, y: 2 }, shape: box(0.4, 0.3) }))
    const [b0, b1, b2, b3, b4, b5, b6, b7] = bodies
    world.createJoint({
      type: 'weld',
      bodyA: b0,
      bodyB: b1,
      anchor: { x: 500, y: 2 },
      linearHertz: 1e6,
      angularHertz: 1e6,
    })
    world.createJoint({ type: 'weld', bodyA: b0, bodyB: b1, anchor: { x: -500, y: 2 } })
    world.createJoint({
      type: 'prismatic',
      bodyA: b2,
      bodyB: b3,
      anchor: { x: -3, y: 2 },
      axis: { x: 1e-6, y: 1 },
      enableMotor: true,
      motorSpeed: 1e6,
      maxMotorForce: 1e12,
      enableSpring: true,
      hertz: 1e6,
      enableLimit: true,
      lower: -1e5,
      upper: 1e5,
    })
    world.createJoint({
      type: 'wheel',
      bodyA: b4,
      bodyB: b5,
      anchor: { x: 500, y: -500 },
      axis: { x: 1, y: 1 },
      enableMotor: true,
      motorSpeed: -1e9,
      maxMotorTorque: 1e12,
      hertz: 1e6,
    })
    const m = world.createJoint({
      type: 'motor',
      bodyA: b6,
      bodyB: b7,
      maxForce: 1e12,
      maxTorque: 1e12,
      correctionFactor: 1,
    })
    world.setJointTarget(m, { x: 1e5, y: -1e5 }, 1e3)
    world.createJoint({
      type: 'revolute',
      bodyA: b6,
      bodyB: b7,
      anchor: { x: 6, y: 2 },
      enableSpring: true,
      hertz: 1e6,
      targetAngle: 3,
    })
    world.createJoint({
      type: 'distance',
      bodyA: null,
      bodyB: b7,
      anchorA: { x: 0, y: 40 },
      anchorB: world.getPosition(b7),
      length: 1,
      minLength: 0,
      maxLength: 1,
      enableMotor: true,
      motorSpeed: 1e6,
      maxMotorForce: 1e12,
    })
    expect(() =>
      world.createJoint({
        type: 'prismatic',
        bodyA: b2,
        bodyB: b3,
        anchor: { x: 0, y: 0 },
        axis: { x: 0, y: 0 },
      }),
    ).toThrow(/axis/)
    expect(() => world.createJoint({ type: 'motor', bodyA: b2, bodyB: b3, correctionFactor: 2 })).toThrow(
      /correctionFactor/,
    )
    const maxSpeed = 400 * 1.15
    for (let s = 0; s < 600; s++) {
      world.step()
      for (const id of world.bodyIds()) {
        const p = world.getPosition(id)
        const v = world.getLinearVelocity(id)
        expect(Number.isFinite(p.x + p.y + v.x + v.y + world.getAngularVelocity(id))).toBe(true)
        expect(Math.hypot(v.x, v.y)).toBeLessThan(maxSpeed)
      }
    }
  })
})
