/*
 * The engine work of one room worker, without the server: K worlds of the capacity scene stepped
 * in turn, each with players dragging bodies like the load bots. Used by bench/engine-ab.ts
 * (scene rooms-K) and bench/room-cache-bench.ts. It takes an engine module as an argument, so
 * engine-ab can step several versions of the engine side by side.
 */

/** The part of a world these benchmarks call. */
export interface EngineWorld {
  step(): void
  hash(): number
  save(): Uint8Array
  bodyIds(): number[]
  getBodyType(id: number): string
  getMass(id: number): number
  getPosition(id: number): { x: number; y: number }
  createJoint(def: {
    type: 'mouse'
    body: number
    target: { x: number; y: number }
    localAnchor: { x: number; y: number }
    maxForce: number
  }): number
  destroyJoint(id: number): void
  setJointTarget(id: number, target: { x: number; y: number }): void
}

/** The part of a scene blueprint these benchmarks read or rewrite. */
export interface Blueprint {
  gravity: { x: number; y: number }
  bodies: { type?: string; enableSleep?: boolean }[]
}

/** The part of an engine version's index.ts the rooms scene needs. */
export interface RoomsEngine {
  createWorld(def: { gravity: { x: number; y: number }; enableSleep: boolean }): EngineWorld
  buildScene(world: unknown, blueprint: unknown): unknown
  pileScene(count: number): Blueprint
}

/** Something stepped as one unit: one world, or all the rooms of a worker. */
export interface Stepper {
  step(): void
  hash(): number
}

/** The blueprint with every dynamic body's enableSleep false: the server capacity scene's pile (bench/server-load.ts awakePile). */
export function awakeBlueprint<T extends Blueprint>(blueprint: T): T {
  return {
    ...blueprint,
    bodies: blueprint.bodies.map((b) => (b.type === 'static' ? b : { ...b, enableSleep: false })),
  } as T
}

/** Players per room, and the bots' drag (bots/bots.ts): 80 of every 100 of their 20 Hz steps. */
const ROOM_PLAYERS = 5
const DRAG_TICKS = 240
const CYCLE_TICKS = 300
/** The pile of 100 and the 15 bodies its 5 bots spawn. */
const ROOM_BODIES = 115

/** A worker's rooms: step() steps every room once, in order; worlds are exposed for save and load. */
export interface Rooms extends Stepper {
  readonly worlds: EngineWorld[]
}

/**
 * K worlds of the capacity scene (pile-115-awake), stepped one after another, so each world's data
 * has left the caches when its turn comes, as on a server. In each, 5 players drag bodies like
 * the bots: a mouse joint with the server's grab force (1000 N per kg) moves its body round a
 * circle of 4 m about (0, 6) m in 240 ticks, lets go for 60, then takes the next body; the
 * players start their cycles 60 ticks apart.
 */
export function roomsStepper(engine: RoomsEngine, rooms: number, sleep: boolean): Rooms {
  const worlds: EngineWorld[] = []
  for (let r = 0; r < rooms; r++) {
    const blueprint = awakeBlueprint(engine.pileScene(ROOM_BODIES))
    const world = engine.createWorld({ gravity: blueprint.gravity, enableSleep: sleep })
    engine.buildScene(world, blueprint)
    worlds.push(world)
  }
  const grabs = worlds.map(() => new Array<number>(ROOM_PLAYERS).fill(-1))
  let tick = 0
  const drive = (r: number): void => {
    const world = worlds[r]
    for (let p = 0; p < ROOM_PLAYERS; p++) {
      const phase = (tick + 60 * p + 7 * r) % CYCLE_TICKS
      if (phase === 0) {
        const ids = world.bodyIds().filter((id) => world.getBodyType(id) === 'dynamic')
        const body = ids[(17 * p + 31 * r + 13 * Math.floor(tick / CYCLE_TICKS)) % ids.length]
        const target = world.getPosition(body)
        const maxForce = 1000 * world.getMass(body)
        grabs[r][p] = world.createJoint({
          type: 'mouse',
          body,
          target,
          localAnchor: { x: 0, y: 0 },
          maxForce,
        })
      } else if (phase === DRAG_TICKS && grabs[r][p] >= 0) {
        world.destroyJoint(grabs[r][p])
        grabs[r][p] = -1
      } else if (phase < DRAG_TICKS && grabs[r][p] >= 0 && phase % 3 === 0) {
        const a = (phase / DRAG_TICKS) * 2 * Math.PI
        world.setJointTarget(grabs[r][p], { x: 4 * Math.cos(a), y: 6 + 3 * Math.sin(a) })
      }
    }
  }
  return {
    worlds,
    step() {
      for (let r = 0; r < worlds.length; r++) {
        drive(r)
        worlds[r].step()
      }
      tick++
    },
    hash() {
      let h = 0
      for (const world of worlds) h = (Math.imul(h, 31) + world.hash()) >>> 0
      return h
    },
  }
}
