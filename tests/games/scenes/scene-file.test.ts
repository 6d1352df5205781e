/*
 * Scene files (games/scenes, docs/scene-format.md): exact round trips over every scene and every
 * shape and joint kind, hand-written files against closed-form masses and hand-set values, every
 * refusal naming its field, and the published JSON Schema equal to the one the code checks with.
 */
import { readFileSync } from 'node:fs'
import { describe, expect, it } from 'vitest'
import {
  box,
  buildScene as buildBlueprint,
  capsule,
  circle,
  createWorld,
  machinesScene,
  polygon,
  SCENES,
  segment,
  type World,
} from '../../../engine/index.ts'
import {
  buildScene,
  parseScene,
  SCENE_LIMITS,
  SCENE_SCHEMA,
  type SceneFile,
  saveScene,
  sceneText,
} from '../../../games/index.ts'

/** Parse and build a scene text, failing the test with the error if either refuses. */
function open(text: string): World {
  const parsed = parseScene(text)
  if (!parsed.ok) throw new Error(parsed.error)
  const built = buildScene(parsed.scene)
  if (!built.ok) throw new Error(built.error)
  return built.built.world
}

/** Why a scene text is refused (parse or build), or null. */
function refusal(text: string): string | null {
  const parsed = parseScene(text)
  if (!parsed.ok) return parsed.error
  const built = buildScene(parsed.scene)
  return built.ok ? null : built.error
}

/** Every shape kind, compound bodies, filters, sensors, damping, a bullet, a kinematic body, all joint kinds. */
function everyKindWorld(): World {
  const world = createWorld({ gravity: { x: 0.5, y: -9 } })
  buildBlueprint(world, machinesScene())
  const a = world.createBody({
    position: { x: 3, y: 30 },
    angle: 0.7,
    linearVelocity: { x: 1.5, y: -2 },
    angularVelocity: 0.3,
    linearDamping: 0.1,
    angularDamping: 0.2,
    gravityScale: 0.5,
    bullet: true,
    shapes: [
      { shape: box(1, 0.2), density: 2, friction: 0.3, restitution: 0.4 },
      { shape: circle(0.3, { x: 1, y: 0.1 }), filter: { categoryBits: 2, maskBits: 5, groupIndex: -3 } },
      { shape: capsule({ x: -1, y: 0 }, { x: -1, y: 1 }, 0.15) },
      {
        shape: polygon(
          [
            { x: 0, y: 1 },
            { x: 0.5, y: 1.2 },
            { x: 0.2, y: 1.6 },
          ],
          0.05,
        ),
      },
      { shape: box(0.3, 0.2, { x: 0.5, y: -0.5 }, 0.4) },
      { shape: circle(0.5), sensor: true },
    ],
  })
  world.createBody({
    type: 'kinematic',
    position: { x: -5, y: 20 },
    angularVelocity: 1,
    fixedRotation: false,
    shapes: [{ shape: segment({ x: -1, y: 0 }, { x: 1, y: 0 }) }, { shape: box(0.2, 0.2) }],
  })
  world.createBody({
    type: 'static',
    position: { x: 9, y: 2 },
    shape: segment({ x: 0, y: 0 }, { x: 3, y: 1 }),
  })
  world.createJoint({
    type: 'revolute',
    bodyA: null,
    bodyB: a,
    anchor: { x: 3, y: 31 },
    enableLimit: true,
    lowerAngle: -0.5,
    upperAngle: 0.25,
    enableSpring: true,
    hertz: 2,
    targetAngle: 0.1,
    breakForce: 5000,
  })
  return world
}

/** The worlds the round trip runs over: every named scene and the every-kind world. */
function roundTripWorlds(): Array<[string, () => World]> {
  const named = Object.keys(SCENES).map((name): [string, () => World] => [
    name,
    () => {
      const w = createWorld()
      buildBlueprint(w, SCENES[name].make())
      return w
    },
  ])
  return [...named, ['every-kind', everyKindWorld]]
}

describe('scene file round trip', () => {
  it.each(roundTripWorlds())(
    '%s: save -> open -> save gives the same file, and two opens step alike',
    (name, make) => {
      const world = make()
      for (let i = 0; i < 75; i++) world.step()
      // Change settings after creation: the file keeps the joint as it stands.
      const motorJoint = world.joints().find((j) => j.type === 'wheel' || j.type === 'revolute')
      if (motorJoint) world.setJointMotorSpeed(motorJoint.id, -3.25)
      const first = sceneText(saveScene(world, { name }))
      const opened = open(first)
      const second = sceneText(saveScene(opened, { name }))
      expect(second).toBe(first)
      expect(opened.bodyCount).toBe(world.bodyCount)
      expect(opened.jointIds().length).toBe(world.joints().filter((j) => j.type !== 'mouse').length)
      // The opened world holds the saved world's bodies exactly (ids renumbered in file order).
      const ids = world.bodyIds()
      const openedIds = opened.bodyIds()
      for (let i = 0; i < ids.length; i++) {
        expect(opened.getPosition(openedIds[i])).toEqual(world.getPosition(ids[i]))
        expect(opened.getRotation(openedIds[i])).toEqual(world.getRotation(ids[i]))
        expect(opened.getLinearVelocity(openedIds[i])).toEqual(world.getLinearVelocity(ids[i]))
        expect(opened.getMass(openedIds[i])).toBe(world.getMass(ids[i]))
      }
      // Two worlds opened from the same file are the same world, now and after stepping.
      const again = open(second)
      expect(again.hash()).toBe(opened.hash())
      for (let i = 0; i < 60; i++) {
        opened.step()
        again.step()
      }
      expect(again.hash()).toBe(opened.hash())
    },
  )

  it('keeps joint settings changed after creation and the motor speed set through the API', () => {
    const world = createWorld()
    buildBlueprint(world, machinesScene())
    const wheel = world.joints().find((j) => j.type === 'wheel')
    if (!wheel) throw new Error('machines scene has no wheel joint')
    world.setJointMotorSpeed(wheel.id, 7.5)
    const scene = saveScene(world)
    const saved = scene.joints?.find((j) => j.type === 'wheel')
    expect(saved?.motorSpeed).toBe(7.5)
    const kinds = new Set(scene.joints?.map((j) => j.type))
    expect([...kinds].sort()).toEqual(['distance', 'motor', 'prismatic', 'revolute', 'weld', 'wheel'])
  })
})

describe('surface materials in scene files', () => {
  /**
   * A conveyor (a static box whose top moves at +2 m/s) carrying a box at rest, and a disc rolling
   * at 3 m/s on ground with rolling resistance 0.06, friction 1 everywhere, g = 10.
   */
  function surfaces(): World {
    const world = createWorld({ gravity: { x: 0, y: -10 } })
    world.createBody({
      type: 'static',
      position: { x: 0, y: -0.5 },
      shapes: [{ shape: box(40, 0.5), friction: 1, tangentSpeed: 2 }],
    })
    world.createBody({ position: { x: 0, y: 0.25 }, shapes: [{ shape: box(0.25, 0.25), friction: 1 }] })
    world.createBody({
      type: 'static',
      position: { x: 0, y: -20.5 },
      shapes: [{ shape: box(40, 0.5), friction: 1, rollingResistance: 0.06 }],
    })
    world.createBody({
      position: { x: -30, y: -19.5 },
      linearVelocity: { x: 3, y: 0 },
      angularVelocity: -6,
      shapes: [{ shape: circle(0.5), friction: 1 }],
    })
    return world
  }

  it('keeps rollingResistance and tangentSpeed: the same file back, the belt carries, the disc slows at (2/3) c g', () => {
    const world = surfaces()
    const text = sceneText(saveScene(world))
    const parsed = parseScene(text)
    if (!parsed.ok) throw new Error(parsed.error)
    expect(parsed.scene.bodies[0].shapes[0]).toMatchObject({ tangentSpeed: 2 })
    expect(parsed.scene.bodies[2].shapes[0]).toMatchObject({ rollingResistance: 0.06 })
    // Left out at their defaults: a world without them saves what it saved before they existed.
    expect(parsed.scene.bodies[1].shapes[0]).not.toHaveProperty('tangentSpeed')
    expect(parsed.scene.bodies[1].shapes[0]).not.toHaveProperty('rollingResistance')
    const opened = open(text)
    expect(sceneText(saveScene(opened))).toBe(text)
    const [belt, load, ground, disc] = opened.bodyIds()
    expect(opened.getShapeDef(opened.bodyShapes(belt)[0])).toMatchObject({ tangentSpeed: 2 })
    expect(opened.getShapeDef(opened.bodyShapes(ground)[0])).toMatchObject({ rollingResistance: 0.06 })
    for (let i = 0; i < 60; i++) opened.step()
    // Friction (mu g = 10 m/s^2) brings the box to the belt's 2 m/s within 0.2 s; then it rides.
    expect(opened.getLinearVelocity(load).x).toBeCloseTo(2, 2)
    // Rolling without slipping, the disc loses (2/3) c g = 0.4 m/s per second: 3 -> 2.6 after 1 s.
    expect(opened.getLinearVelocity(disc).x).toBeCloseTo(2.6, 1)
  })
})

/** A hand-written scene: one ground box, one disc, one box hinged to the world, gravity (0, -9.81). */
const HAND_SCENE = `{
  "format": "concord-scene", "version": 1, "name": "hand",
  "gravity": {"x": 0, "y": -9.81},
  "bodies": [
    {"type": "static", "position": {"x": 0, "y": -1}, "shapes": [{"type": "box", "halfWidth": 20, "halfHeight": 1}]},
    {"type": "dynamic", "position": {"x": 1, "y": 2}, "angle": 0.5, "linearVelocity": {"x": 3, "y": 0},
     "color": "#FF8800", "shapes": [{"type": "circle", "radius": 0.5, "density": 2, "friction": 0.2, "restitution": 0.75}]},
    {"type": "dynamic", "position": {"x": -3, "y": 4}, "shapes": [{"type": "box", "halfWidth": 1, "halfHeight": 0.25}]}
  ],
  "joints": [
    {"type": "revolute", "bodyA": null, "bodyB": 2, "anchor": {"x": -4, "y": 4}, "enableMotor": true,
     "motorSpeed": 2, "maxMotorTorque": 50}
  ]
}`

describe('a hand-written scene file', () => {
  it('builds the bodies, materials and joint it describes (masses by closed form)', () => {
    const parsed = parseScene(HAND_SCENE)
    if (!parsed.ok) throw new Error(parsed.error)
    const built = buildScene(parsed.scene)
    if (!built.ok) throw new Error(built.error)
    const { world, bodies, colors } = built.built
    expect(world.getGravity()).toEqual({ x: 0, y: -9.81 })
    expect(bodies).toEqual([1, 2, 3])
    // Disc: m = density pi r^2 = 2 pi 0.25; box: 1 * (2 * 0.5) * 2 = 2 kg... (2 hw)(2 hh) = 2 * 0.5 = 1 m^2.
    expect(world.getMass(2)).toBeCloseTo(2 * Math.PI * 0.25, 12)
    expect(world.getMass(3)).toBeCloseTo(1, 12)
    expect(world.getPosition(2)).toEqual({ x: 1, y: 2 })
    expect(world.getAngle(2)).toBeCloseTo(0.5, 12)
    expect(world.getLinearVelocity(2)).toEqual({ x: 3, y: 0 })
    const disc = world.getShapeDef(world.bodyShapes(2)[0])
    expect([disc.density, disc.friction, disc.restitution]).toEqual([2, 0.2, 0.75])
    expect(world.getShapeDef(world.bodyShapes(3)[0]).friction).toBe(0.6) // the engine's default
    expect(colors.get(2)).toBe('#ff8800')
    const [joint] = world.joints()
    expect(joint.type).toBe('revolute')
    expect(joint.bodyA).toBeNull()
    expect(joint.anchorA).toEqual({ x: -4, y: 4 })
    const def = world.getJointDef(joint.id)
    expect(def.type === 'revolute' && [def.enableMotor, def.motorSpeed, def.maxMotorTorque]).toEqual([
      true,
      2,
      50,
    ])
  })

  it('saves a known world as the fields it was given', () => {
    const world = createWorld({ gravity: { x: 0, y: -10 } })
    world.createBody({
      position: { x: 1, y: 2 },
      linearVelocity: { x: 0.5, y: 0 },
      shape: box(0.5, 0.25),
      density: 3,
      restitution: 0.5,
    })
    const scene = saveScene(world, { name: 'known', colorOf: () => '#123456' })
    expect(scene).toEqual({
      format: 'concord-scene',
      version: 1,
      name: 'known',
      gravity: { x: 0, y: -10 },
      bodies: [
        {
          type: 'dynamic',
          position: { x: 1, y: 2 },
          angle: 0,
          rotation: { c: 1, s: 0 },
          linearVelocity: { x: 0.5, y: 0 },
          angularVelocity: 0,
          color: '#123456',
          shapes: [
            { type: 'box', halfWidth: 0.5, halfHeight: 0.25, density: 3, friction: 0.6, restitution: 0.5 },
          ],
        },
      ],
      joints: [],
    })
  })
})

/** HAND_SCENE with a change made to its parsed value. */
function edited(change: (scene: SceneFile & Record<string, unknown>) => void): string {
  const scene = JSON.parse(HAND_SCENE)
  change(scene)
  return JSON.stringify(scene)
}

describe('refusals name the field', () => {
  const cases: Array<[string, string, string]> = [
    ['not JSON', '{"format": ', 'the scene file is not JSON'],
    ['a list', '[]', 'a scene file must be a JSON object'],
    [
      'another format',
      edited((s) => (s.format = 'rube' as 'concord-scene')),
      'format must be "concord-scene"',
    ],
    [
      'a later version',
      edited((s) => (s.version = 2)),
      'version 2 is not supported: this build reads scene format version 1',
    ],
    [
      'a zero radius',
      edited((s) => (s.bodies[1].shapes[0].radius = 0)),
      'bodies[1].shapes[0].radius must be > 0',
    ],
    [
      'a negative radius',
      edited((s) => (s.bodies[1].shapes[0].radius = -1)),
      'bodies[1].shapes[0].radius must be >= 0',
    ],
    [
      'a missing half width',
      edited((s) => delete s.bodies[0].shapes[0].halfWidth),
      'bodies[0].shapes[0].halfWidth is required for a box',
    ],
    [
      'a circle with vertices',
      edited(
        (s) =>
          (s.bodies[1].shapes[0].vertices = [
            { x: 0, y: 0 },
            { x: 1, y: 0 },
            { x: 0, y: 1 },
          ]),
      ),
      'bodies[1].shapes[0].vertices is not a field of a circle',
    ],
    [
      'an unknown shape kind',
      edited((s) => (s.bodies[1].shapes[0].type = 'chain' as 'circle')),
      'bodies[1].shapes[0].type must be equal to one of the allowed values',
    ],
    [
      'friction out of range',
      edited((s) => (s.bodies[1].shapes[0].friction = 101)),
      'bodies[1].shapes[0].friction must be <= 100',
    ],
    ['a bad colour', edited((s) => (s.bodies[1].color = 'red')), 'bodies[1].color must match pattern'],
    [
      'an unknown body field',
      edited((s) => ((s.bodies[1] as unknown as Record<string, unknown>).mass = 3)),
      'bodies[1].mass is not allowed',
    ],
    [
      'no shapes',
      edited((s) => (s.bodies[1].shapes = [])),
      'bodies[1].shapes must NOT have fewer than 1 items',
    ],
    [
      'a missing position',
      edited((s) => delete (s.bodies[2] as unknown as Record<string, unknown>).position),
      'bodies[2].position is required',
    ],
    [
      'a joint body out of range',
      edited((s) => (s.joints = [{ ...(s.joints?.[0] as object), bodyB: 3 } as never])),
      'joints[0].bodyB must be < 3 (the number of bodies)',
    ],
    [
      'a joint of one body',
      edited((s) => (s.joints = [{ ...(s.joints?.[0] as object), bodyA: 2 } as never])),
      'joints[0].bodyB must differ from bodyA',
    ],
    [
      'a field of another joint kind',
      edited((s) => s.joints && (s.joints[0].length = 2)),
      'joints[0].length is not a field of a revolute joint',
    ],
    [
      'a joint without an anchor',
      edited((s) => s.joints && delete s.joints[0].anchor),
      'joints[0].anchor is required',
    ],
    [
      'frames and anchors both',
      edited((s) => s.joints && (s.joints[0].localAnchorA = { x: 0, y: 0 })),
      'joints[0] gives both local frames and world anchors; give one',
    ],
    [
      'a concave polygon',
      edited(
        (s) =>
          (s.bodies[2].shapes[0] = {
            type: 'polygon',
            vertices: [
              { x: 0, y: 0 },
              { x: 2, y: 0 },
              { x: 1, y: 0.2 },
              { x: 2, y: 2 },
              { x: 0, y: 2 },
            ],
          }),
      ),
      'bodies[2].shapes[0]: ',
    ],
    [
      'a dynamic body of segments',
      edited(
        (s) => (s.bodies[2].shapes[0] = { type: 'segment', point1: { x: 0, y: 0 }, point2: { x: 1, y: 0 } }),
      ),
      'bodies[2]: a dynamic body needs a shape with mass',
    ],
    [
      'an angle that contradicts the rotation',
      edited((s) => (s.bodies[1].rotation = { c: 1, s: 0 })),
      'bodies[1].angle disagrees with bodies[1].rotation',
    ],
    [
      'a rotation that is not unit',
      edited((s) => {
        s.bodies[1].rotation = { c: 2, s: 0 }
        delete s.bodies[1].angle
      }),
      'bodies[1]: rotation must have length 1',
    ],
    [
      'an infinite limit break (upper below lower)',
      edited(
        (s) =>
          s.joints && Object.assign(s.joints[0], { enableLimit: true, lowerAngle: 0.5, upperAngle: 0.1 }),
      ),
      'joints[0]: upperAngle must be',
    ],
  ]
  it.each(cases)('%s', (_what, text, expected) => {
    const error = refusal(text)
    expect(error).not.toBeNull()
    expect(error).toContain(expected)
  })

  it('refuses a file over the byte limit before parsing it, naming both sizes', () => {
    const text = `${HAND_SCENE}${' '.repeat(SCENE_LIMITS.bytes)}`
    expect(refusal(text)).toBe(`the scene file is ${text.length} bytes; the limit is ${SCENE_LIMITS.bytes}`)
  })

  it('refuses more bodies, shapes or joints than the limits', () => {
    const body = { type: 'static', position: { x: 0, y: 0 }, shapes: [{ type: 'circle', radius: 0.1 }] }
    const many = (n: number) =>
      JSON.stringify({
        format: 'concord-scene',
        version: 1,
        gravity: { x: 0, y: 0 },
        bodies: Array(n).fill(body),
      })
    expect(refusal(many(SCENE_LIMITS.bodies))).toBeNull()
    expect(refusal(many(SCENE_LIMITS.bodies + 1))).toBe(
      `bodies must NOT have more than ${SCENE_LIMITS.bodies} items`,
    )
    const heavy = { ...body, shapes: Array(5).fill(body.shapes[0]) }
    const shapes = JSON.stringify({
      format: 'concord-scene',
      version: 1,
      gravity: { x: 0, y: 0 },
      bodies: Array(SCENE_LIMITS.shapes / 5 + 1).fill(heavy),
    })
    expect(refusal(shapes)).toBe(`bodies holds more than ${SCENE_LIMITS.shapes} shapes in all`)
  })
})

describe('the published schema', () => {
  it('docs/scene-format.schema.json is the schema the code checks with', () => {
    const published = JSON.parse(
      readFileSync(new URL('../../../docs/scene-format.schema.json', import.meta.url), 'utf8'),
    )
    expect(published).toEqual(JSON.parse(JSON.stringify(SCENE_SCHEMA)))
  })
})
