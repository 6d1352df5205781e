/*
 * The five-storey card house of issue 27 (cardHouseScene(5)'s 40 cards on a 4 m thick ground box,
 * friction 0.7) built in a chosen creation order, mirrored or jittered, and the battery of 66 such
 * builds. No Node APIs: tests/engine/card-house.test.ts bundles runBattery with esbuild and runs it
 * in a plain node process (under vitest's module runner the engine steps about four times slower).
 */
import { type BodyDef, box, cardHouseScene, createWorld, type World } from '../../engine/index.ts'

/** A card that has moved this far has fallen (a fallen card moves by about its height, 0.4 m). */
export const STANDING = 0.05
export const STEPS = 600 // 10 s

export interface Variant {
  /** -1: the cards created top storey first; 0: as cardHouseScene lists them; > 0: a shuffle seed. */
  order: number
  mirrored: boolean
  /** Each card's position moved by up to +-jitter / 2 per axis (m). */
  jitter: number
}

/**
 * The generator of the runs that put the same 66 builds to Box2D v3.1 (box2d3-wasm 5.2.0, issue 27
 * notes): x <- (1103515245 x + 12345) mod 2^31 in doubles (the product is rounded, the same in
 * every JavaScript engine), returning x / 2^31.
 */
function lcg(seed: number): () => number {
  let x = seed
  return () => {
    x = (x * 1103515245 + 12345) % 2147483648
    return x / 2147483648
  }
}

/** The issue's house: cardHouseScene(5)'s 40 cards on a 4 m thick ground box, friction 0.7. */
export function buildHouse(world: World, v: Variant): { ids: number[]; defs: BodyDef[] } {
  const defs = cardHouseScene(5)
    .bodies.slice(1)
    .map((d) => ({ ...d, position: { x: d.position?.x ?? 0, y: d.position?.y ?? 0 } }))
  if (defs.length !== 40) throw new Error(`cardHouseScene(5) has ${defs.length} cards, not 40`)
  if (v.mirrored) {
    for (const d of defs) {
      d.position.x = -d.position.x
      d.angle = -(d.angle ?? 0)
    }
  }
  if (v.jitter > 0) {
    const jitter = lcg(12345)
    for (const d of defs) {
      d.position.x += v.jitter * (jitter() - 0.5)
      d.position.y += v.jitter * (jitter() - 0.5)
    }
  }
  const order = defs.map((_, i) => i)
  if (v.order === -1) order.reverse()
  if (v.order > 0) {
    const shuffle = lcg(v.order)
    for (let i = order.length - 1; i > 0; i--) {
      const j = Math.floor(shuffle() * (i + 1))
      ;[order[i], order[j]] = [order[j], order[i]]
    }
  }
  world.createBody({ type: 'static', position: { x: 0, y: -2 }, shape: box(40, 2), friction: 0.7 })
  const ordered = order.map((i) => defs[i])
  return { ids: ordered.map((d) => world.createBody(d)), defs: ordered }
}

export function worstDrift(world: World, ids: number[], defs: BodyDef[]): number {
  let worst = 0
  ids.forEach((id, k) => {
    const p = world.getPosition(id)
    const start = defs[k].position ?? { x: 0, y: 0 }
    worst = Math.max(worst, Math.hypot(p.x - start.x, p.y - start.y))
  })
  return worst
}

/** The 66 builds: creation orders -1..20, each as built, mirrored and jittered 0.3 mm. */
export function batteryVariants(): Variant[] {
  const out: Variant[] = []
  for (let order = -1; order <= 20; order++) {
    out.push(
      { order, mirrored: false, jitter: 0 },
      { order, mirrored: true, jitter: 0 },
      { order, mirrored: false, jitter: 0.0003 },
    )
  }
  return out
}

/** Each build's worst card drift (m) after STEPS steps with sleeping off. */
export function runBattery(): Array<Variant & { drift: number }> {
  return batteryVariants().map((v) => {
    const world = createWorld({ enableSleep: false })
    const { ids, defs } = buildHouse(world, v)
    for (let i = 0; i < STEPS; i++) world.step()
    return { ...v, drift: worstDrift(world, ids, defs) }
  })
}
