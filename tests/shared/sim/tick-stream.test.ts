/*
 * The tick stream's entry codec against hand-written wire arrays (PROTOCOL.md's kind table) and
 * a round trip of every kind through real MessagePack; malformed entries come back as reasons.
 */
import { describe, expect, it } from 'vitest'
import {
  type Command,
  decodeEntries,
  decodeValue,
  encodeEntry,
  encodeValue,
  type StreamAction,
} from '../../../shared/index.ts'

const ACTIONS: Array<[StreamAction, unknown[]]> = [
  [{ k: 'join' }, [0]],
  [{ k: 'leave' }, [1]],
  [
    { k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.25 }, x: 1.1, y: 2.2, vx: -3 },
    [2, { type: 'box', hw: 0.5, hh: 0.25 }, 1.1, 2.2, null, -3, null, null],
  ],
  [{ k: 'grab', body: 7, lx: 0.1, ly: -0.2 }, [3, 7, 0.1, -0.2]],
  [{ k: 'move', x: Math.PI, y: -1e-9 }, [4, Math.PI, -1e-9]],
  [{ k: 'release' }, [5]],
  [{ k: 'delete', body: 9 }, [6, 9]],
  [{ k: 'pin', a: 0, b: 4, x: 1, y: 2 }, [7, 0, 4, 1, 2]],
  [{ k: 'rope', a: 3, b: 4, ax: 1, ay: 2, bx: 3, by: 4 }, [8, 3, 4, 1, 2, 3, 4]],
  [{ k: 'unjoint', joint: 12 }, [9, 12]],
  [{ k: 'scene', name: 'pile' }, [10, 'pile']],
  [{ k: 'pause', paused: true }, [11, true]],
  [{ k: 'step' }, [12]],
  [{ k: 'reset' }, [13]],
  [{ k: 'gravity', x: 0, y: -9.81 }, [14, 0, -9.81]],
  [
    { k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 3, friction: 0.1, restitution: 0.9 },
    [2, { type: 'circle', radius: 0.5 }, 0, 3, null, null, null, null, null, 0.1, 0.9, null, null],
  ],
  [
    {
      k: 'spawn',
      shapes: [
        { type: 'capsule', v: [-0.5, 0, 0.5, 0], radius: 0.2, friction: 0.1 },
        { type: 'circle', radius: 0.3, x: 0, y: 0.4, sensor: true },
      ],
      x: 1,
      y: 4,
      color: 0x3cb44b,
    },
    [
      2,
      [
        { type: 'capsule', v: [-0.5, 0, 0.5, 0], radius: 0.2, friction: 0.1 },
        { type: 'circle', radius: 0.3, x: 0, y: 0.4, sensor: true },
      ],
      1,
      4,
      null,
      null,
      null,
      null,
      null,
      null,
      null,
      0x3cb44b,
      null,
    ],
  ],
  [
    { k: 'spawn', outline: [0, 0, 2, 0, 2, 2, 1, 0.5, 0, 2], x: 0, y: 1, static: true },
    [
      2,
      { outline: [0, 0, 2, 0, 2, 2, 1, 0.5, 0, 2] },
      0,
      1,
      null,
      null,
      null,
      null,
      null,
      null,
      null,
      null,
      true,
    ],
  ],
]

describe('tick stream entries', () => {
  it('encode every kind as PROTOCOL.md lists it: [tick offset, player, kind, ...arguments]', () => {
    for (const [action, wire] of ACTIONS) {
      expect(encodeEntry({ tick: 105, player: 3, action }, 100)).toEqual([5, 3, ...wire])
    }
  })

  it('round-trip every kind through MessagePack with float64 values bit for bit', () => {
    const list = ACTIONS.map(([action], i) => encodeEntry({ tick: 10 + (i >> 2), player: i + 1, action }, 10))
    const decoded = decodeValue(encodeValue(list))
    expect(decoded.ok).toBe(true)
    const result = decodeEntries(decoded.ok ? decoded.value : null, 10, 5)
    expect(result.ok).toBe(true)
    if (!result.ok) return
    expect(result.entries.map((e) => e.action)).toEqual(ACTIONS.map(([a]) => a))
    expect(result.entries.map((e) => e.tick)).toEqual(ACTIONS.map((_, i) => 10 + (i >> 2)))
    const move = result.entries[4].action as Extract<Command, { k: 'move' }>
    expect(Object.is(move.y, -1e-9)).toBe(true)
  })

  it('refuse malformed lists with a reason naming the problem', () => {
    const bad: Array<[unknown, RegExp]> = [
      ['nope', /must be a list/],
      [[[0, 1]], /at least 3/],
      [[[5, 1, 4, 0, 0]], /out of order/],
      [
        [
          [1, 1, 5],
          [0, 1, 5],
        ],
        /out of order/,
      ],
      [[[0, 1, 99]], /unknown kind 99/],
      [[[0, 1, 4, 1]], /needs 2 arguments/],
      [[[0, 1, 4, 1, Number.NaN]], /finite/],
      [[[0, -1, 5]], /player/],
      [[[0, 1, 3, 1.5, 0, 0]], /body/],
      [
        [[0, 1, 2, { type: 'blob' }, 0, 0, null, null, null, null]],
        /"circle", "box", "polygon", "capsule", "segment" or "chain"/,
      ],
      [[[0, 1, 11, 'yes']], /true or false/],
    ]
    for (const [list, reason] of bad) {
      const r = decodeEntries(list, 0, 3)
      expect(r.ok).toBe(false)
      if (!r.ok) expect(r.reason).toMatch(reason)
    }
  })

  it('refuse inspect: it is never part of the simulation', () => {
    expect(() => encodeEntry({ tick: 1, player: 1, action: { k: 'inspect', body: 3 } }, 0)).toThrow(
      /never streamed/,
    )
  })
})
