/*
 * The scenes of allocation.test.ts, stepped in the measuring process of tests/support/measure-allocation.ts
 * (bundled with esbuild, run in a separate quiet `node --expose-gc` process).
 *
 * - pile: a 300-body pile (pileScene(300), sleeping off, so every body is simulated every step) and,
 *   beside it, two alternating towers of 20 and 50 boxes (column contacts, contact-columns.ts) and
 *   the five-storey card house (slender cards: the leaning ones' contacts get extra sweeps).
 * - room: the server's capacity room without the server: a 100-body pile whose bodies never sleep
 *   (bench/server-load.ts awakePile) and five players, each dragging a random dynamic body with a
 *   mouse joint round an ellipse (half-axes 4 m and 3 m; a lap in 80 of their 20 Hz steps, about
 *   6 m/s: fast bodies, continuous collision, contacts made and broken); once a second the world
 *   is hashed (the recorder's checkpoint, which writes the whole world into a buffer). Every 600
 *   warm-up steps, and before each measured round, the players let go, a body is spawned above the
 *   pile (the oldest spawned one destroyed past 12) and they grab five new bodies: those commands
 *   allocate (bodies, joints, id lists), so they run outside the measured rounds, while the steps
 *   after them (a new body's first contacts, a grab's first pull) are measured.
 * - machines: machinesScene (every joint kind: wheel, prismatic, weld, distance with a motor,
 *   revolute with a spring, motor joint; the bridge's breakable pins break in the warm-up), driven
 *   as a game would: the car's and the crane's motors reverse every 5 s (setJointMotorSpeed), the
 *   motor joint's offset goes round a circle (setJointTarget with a reused point), the piston's and
 *   the counterweight's targets move, and the world is hashed once a second.
 * - compound: 150 compound bodies (dumbbells, capsules with a fin, rounded triangles with a ball) on
 *   static segments, two sensors (one on a turning kinematic body), hit events on half the bodies;
 *   every step reads the contact and sensor event lists as a game would. The two floor segments are
 *   conveyors (tangent speed 0.5 m/s) and every other body's shapes have
 *   rolling resistance 0.1, so the solver's tangent-speed and rolling-resistance paths run.
 * - chains: the marble run (marbleRunScene: four one-sided chain tracks, balls and capsules, a bin
 *   whose floor is a sensor), sleeping off, with the marbles recycled: each step the next marble
 *   lying in the bin is put back at the top (setTransform and setLinearVelocity with reused
 *   values), so marbles keep running down the chains, meeting new segments, and the sensor's events
 *   are read every step.
 */
import {
  type BodyId,
  box,
  buildScene,
  capsule,
  cardHouseScene,
  circle,
  createWorld,
  type JointId,
  MARBLE_RUN_LAYOUT,
  machinesScene,
  marbleRunScene,
  Prng,
  pileScene,
  polygon,
  segment,
  type Vec2,
  type World,
} from '../../engine/index.ts'

/**
 * The room's players (see the file comment). Between rounds, `regrab` releases the grabs, spawns a
 * body (destroying the oldest spawned one past 12) and grabs five random dynamic bodies; in a round,
 * `drag(i)` moves each grab's target (allocation-free), every third step per player.
 */
class RoomSchedule {
  private readonly prng = new Prng(7)
  private readonly grabs: JointId[] = []
  private readonly spawned: BodyId[] = []
  private readonly target: Vec2 = { x: 0, y: 0 }
  private spawns = 0

  constructor(private readonly world: World) {}

  /** Releases every grab, spawns a body (and destroys the oldest spawned one past 12), grabs five. */
  regrab(): void {
    const world = this.world
    for (const joint of this.grabs) if (world.hasJoint(joint)) world.destroyJoint(joint)
    this.grabs.length = 0
    this.spawn()
    const ids = world.bodyIds().filter((id) => world.getBodyType(id) === 'dynamic')
    for (let p = 0; p < 5; p++) {
      const body = ids[this.prng.int(ids.length)]
      const target = world.getWorldCenter(body)
      this.grabs.push(
        world.createJoint({ type: 'mouse', body, target, maxForce: 1000 * world.getMass(body) }),
      )
    }
  }

  /** Moves player p's target round its ellipse (a lap in 80 of the player's steps) before step i. */
  drag(i: number): void {
    for (let p = 0; p < this.grabs.length; p++) {
      if ((i + p) % 3 !== 0) continue
      const a = ((((i + p) / 3 + 16 * p) % 80) / 80) * 2 * Math.PI
      this.target.x = 4 * Math.cos(a)
      this.target.y = 6 + 3 * Math.sin(a)
      this.world.setJointTarget(this.grabs[p], this.target)
    }
  }

  private spawn(): void {
    const world = this.world
    const kind = this.spawns++ % 3
    const shape =
      kind === 0
        ? circle(this.prng.range(0.3, 0.6))
        : kind === 1
          ? box(this.prng.range(0.3, 0.6), this.prng.range(0.3, 0.6))
          : polygon([
              { x: -0.4, y: -0.3 },
              { x: 0.4, y: -0.3 },
              { x: 0, y: 0.5 },
            ])
    const position = { x: this.prng.range(-5, 5), y: this.prng.range(8, 12) }
    this.spawned.push(world.createBody({ type: 'dynamic', shape, position }))
    if (this.spawned.length > 12) world.destroyBody(this.spawned.shift()!)
  }
}

/** The machines scene's driver (see the file comment): allocation-free once built. */
class MachineSchedule {
  private readonly wheels: JointId[]
  private readonly rope: JointId
  private readonly platform: JointId
  private readonly piston: JointId
  private readonly springs: JointId[]
  private readonly offset: Vec2 = { x: 0, y: 0 }

  constructor(private readonly world: World) {
    const joints = world.joints()
    const of = (type: string): JointId[] => joints.filter((j) => j.type === type).map((j) => j.id)
    this.wheels = of('wheel')
    this.rope = of('distance')[0]
    this.platform = of('motor')[0]
    this.piston = of('prismatic')[0]
    this.springs = of('revolute').slice(0, 1)
  }

  drive(tick: number): void {
    const world = this.world
    if (tick % 300 === 0) {
      const forward = (tick / 300) % 2 === 0
      for (let i = 0; i < this.wheels.length; i++) world.setJointMotorSpeed(this.wheels[i], forward ? -6 : 6)
      world.setJointMotorSpeed(this.rope, forward ? -0.2 : 0.2)
      world.setJointTarget(this.piston, forward ? 1.5 : 0.2)
      for (let i = 0; i < this.springs.length; i++)
        world.setJointTarget(this.springs[i], forward ? 0.3 : -0.3)
    }
    const a = ((tick % 240) / 240) * 2 * Math.PI
    this.offset.x = 45 + 2 * Math.cos(a)
    this.offset.y = 3 + Math.sin(a)
    world.setJointTarget(this.platform, this.offset)
  }
}

/**
 * 150 compound bodies (dumbbells of two discs on a bar, capsules with a fin, rounded triangles with
 * a ball on top) in a V of static segments with walls, sleeping off: several manifolds per body
 * pair, every pair of kinds.
 */
function buildCompoundPile(world: World): void {
  world.createBody({
    type: 'static',
    shapes: [
      { shape: segment({ x: -12, y: 4 }, { x: 0, y: 0 }), tangentSpeed: 0.5 },
      { shape: segment({ x: 0, y: 0 }, { x: 12, y: 4 }), tangentSpeed: 0.5 },
      { shape: box(0.25, 10, { x: -12, y: 12 }) },
      { shape: box(0.25, 10, { x: 12, y: 12 }) },
      { shape: box(3, 1, { x: -4, y: 3 }), sensor: true },
    ],
  })
  world.createBody({
    type: 'kinematic',
    position: { x: 4, y: 4 },
    angularVelocity: 1,
    shapes: [{ shape: capsule({ x: -2, y: 0 }, { x: 2, y: 0 }, 0.4), sensor: true }],
  })
  const prng = new Prng(3)
  for (let i = 0; i < 150; i++) {
    const position = { x: prng.range(-9, 9), y: 5 + 0.6 * i }
    const angle = prng.range(-3, 3)
    const kind = i % 3
    const shapes =
      kind === 0
        ? [
            { shape: circle(0.3, { x: -0.6, y: 0 }) },
            { shape: box(0.6, 0.1) },
            { shape: circle(0.3, { x: 0.6, y: 0 }) },
          ]
        : kind === 1
          ? [
              { shape: capsule({ x: -0.4, y: 0 }, { x: 0.4, y: 0 }, 0.2) },
              { shape: box(0.08, 0.3, { x: 0, y: 0.3 }, 0.4) },
            ]
          : [
              {
                shape: polygon(
                  [
                    { x: -0.35, y: -0.3 },
                    { x: 0.35, y: -0.3 },
                    { x: 0, y: 0.3 },
                  ],
                  0.05,
                ),
              },
              { shape: circle(0.18, { x: 0, y: 0.5 }) },
            ]
    const rollingResistance = i % 2 === 1 ? 0.1 : 0
    world.createBody({
      position,
      angle,
      shapes: shapes.map((d) => ({ ...d, enableHitEvents: i % 2 === 0, rollingResistance })),
    })
  }
}

/** The marble run's recycler (see the file comment): allocation-free once built. */
class MarbleRecycler {
  private readonly top: Vec2 = { x: -5, y: MARBLE_RUN_LAYOUT.highEnd + 2 }
  private readonly still: Vec2 = { x: 0, y: 0 }
  private readonly position = { x: 0, y: 0 }
  private next = 0

  constructor(
    private readonly world: World,
    private readonly marbles: BodyId[],
  ) {}

  /** Puts the next marble back at the top if it lies in the bin (one per step at most). */
  recycle(): void {
    const world = this.world
    const id = this.marbles[this.next]
    this.next = (this.next + 1) % this.marbles.length
    const p = world.getPosition(id, this.position)
    if (p.y < 1.2 && p.x < MARBLE_RUN_LAYOUT.binRight) {
      world.setTransform(id, this.top, 0)
      world.setLinearVelocity(id, this.still)
    }
  }
}

/** Steps between the room's regrabs in the warm-up (the measured rounds regrab once, first). */
const REGRAB_STEPS = 600

/** One scene of the allocation test: its step, its warm-up and what runs before each round. */
export class AllocationScene {
  readonly world: World
  private readonly schedule: RoomSchedule | null
  private readonly machines: MachineSchedule | null = null
  private readonly marbles: MarbleRecycler | null = null
  private tick = 0
  /** Events read in the compound scene (so the reads cannot be optimized away). */
  eventCount = 0

  constructor(readonly name: 'pile' | 'room' | 'machines' | 'compound' | 'chains') {
    this.world = createWorld(name === 'room' ? {} : { enableSleep: false })
    if (name === 'machines') {
      buildScene(this.world, machinesScene())
      this.machines = new MachineSchedule(this.world)
    } else if (name === 'compound') {
      buildCompoundPile(this.world)
    } else if (name === 'chains') {
      const scene = marbleRunScene()
      const ids = buildScene(this.world, scene)
      this.marbles = new MarbleRecycler(this.world, ids.slice(1, scene.bodies.length))
    } else if (name === 'pile') {
      buildScene(this.world, pileScene(300))
      for (const [x, height] of [
        [40, 20],
        [45, 50],
      ]) {
        for (let i = 0; i < height; i++)
          this.world.createBody({ position: { x: x + (i % 2) * 0.05, y: 0.5 + i }, shape: box(0.5, 0.5) })
      }
      // The five-storey card house on its own ground: slender cards, leaning (extra sweeps) and flat.
      this.world.createBody({ type: 'static', position: { x: 60, y: -0.5 }, shape: box(5, 0.5) })
      for (const card of cardHouseScene(5).bodies.slice(1))
        this.world.createBody({
          ...card,
          position: { x: 60 + (card.position?.x ?? 0), y: card.position?.y ?? 0 },
        })
    } else {
      const pile = pileScene(100)
      buildScene(this.world, {
        ...pile,
        bodies: pile.bodies.map((b) => (b.type === 'static' ? b : { ...b, enableSleep: false })),
      })
    }
    this.schedule = name === 'room' ? new RoomSchedule(this.world) : null
  }

  /** One step: in the room, the players' drags, the step, and once a second a hash. */
  step(): void {
    this.schedule?.drag(this.tick)
    this.machines?.drive(this.tick)
    this.marbles?.recycle()
    this.world.step()
    if (this.name === 'compound' || this.name === 'chains') {
      // Read the events as a game would: the arrays and records are the world's, reused.
      const c = this.world.contactEvents()
      const s = this.world.sensorEvents()
      this.eventCount += c.begin.length + c.end.length + c.hit.length + s.begin.length + s.end.length
    }
    if ((this.schedule !== null || this.machines !== null) && this.tick % 60 === 0) this.world.hash()
    this.tick++
  }

  /** `steps` steps, the room regrabbing every REGRAB_STEPS. */
  warmUp(steps: number): void {
    for (let i = 0; i < steps; i++) {
      if (i % REGRAB_STEPS === 0) this.schedule?.regrab()
      this.step()
    }
  }

  /** Before a measured round: the room's players let go, a body is spawned, they grab again. */
  beforeRound(): void {
    this.schedule?.regrab()
  }

  /** Bodies and contacts now (a real pile has contacts). */
  counts(): { bodies: number; contacts: number; events: number } {
    return { bodies: this.world.bodyCount, contacts: this.world.contacts().length, events: this.eventCount }
  }
}
