import { decode } from '@msgpack/msgpack'
import { describe, expect, it } from 'vitest'
import { decodeClientMessage, encodeMessage } from '../../../shared/protocol/codec.ts'
import { PROTOCOL_VERSION } from '../../../shared/protocol/constants.ts'
import type { ClientMessage } from '../../../shared/protocol/messages.ts'
import { validateClientMessage } from '../../../shared/protocol/validate.ts'

const good: ClientMessage[] = [
  { t: 'join', v: PROTOCOL_VERSION, room: 'lobby', name: 'ada', mode: 'snapshot' },
  { t: 'join', v: PROTOCOL_VERSION, room: '', name: 'ada', mode: 'snapshot', token: 'abc' },
  { t: 'input', seq: 1, cmd: { k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 1, y: 2 } },
  {
    t: 'input',
    seq: 2,
    cmd: { k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 1 }, x: 1, y: 2, angle: 1, vx: 3, vy: 4, w: 5 },
  },
  { t: 'input', seq: 3, cmd: { k: 'spawn', shape: { type: 'polygon', v: [0, 0, 1, 0, 0, 1] }, x: 1, y: 2 } },
  { t: 'input', seq: 4, cmd: { k: 'grab', body: 3, lx: 0.1, ly: -0.2 } },
  { t: 'input', seq: 5, cmd: { k: 'move', x: 3, y: 4 } },
  { t: 'input', seq: 6, cmd: { k: 'release' } },
  { t: 'input', seq: 7, cmd: { k: 'delete', body: 9 } },
  { t: 'input', seq: 8, cmd: { k: 'pin', a: 0, b: 4, x: 1, y: 1 } },
  { t: 'input', seq: 9, cmd: { k: 'rope', a: 2, b: 4, ax: 1, ay: 1, bx: 2, by: 2 } },
  { t: 'input', seq: 10, cmd: { k: 'unjoint', joint: 1 } },
  { t: 'input', seq: 11, cmd: { k: 'scene', name: 'pile' } },
  { t: 'input', seq: 12, cmd: { k: 'pause', paused: true } },
  { t: 'input', seq: 13, cmd: { k: 'step' } },
  { t: 'input', seq: 14, cmd: { k: 'reset' } },
  { t: 'input', seq: 15, cmd: { k: 'gravity', x: 0, y: -9.81 } },
  { t: 'input', seq: 16, cmd: { k: 'inspect', body: 3 } },
  { t: 'input', seq: 17, cmd: { k: 'inspect', body: 0 } },
  { t: 'ack', tick: 120 },
  { t: 'ping', id: 1, time: 12345.678 },
]

describe('client message validation', () => {
  it('every documented client message survives encode, decode and validation unchanged', () => {
    for (const m of good) {
      const r = decodeClientMessage(encodeMessage(m))
      expect(r).toEqual({ ok: true, value: m })
    }
  })

  it('the encoder writes standard MessagePack that an independent decoder reads', () => {
    for (const m of good) expect(decode(encodeMessage(m))).toEqual(m)
  })

  const bad: Array<[string, unknown]> = [
    ['a non-map', [1, 2, 3]],
    ['an unknown type', { t: 'hello' }],
    ['a missing field', { t: 'ack' }],
    ['a string tick', { t: 'ack', tick: '5' }],
    ['a fractional tick', { t: 'ack', tick: 1.5 }],
    ['a negative tick', { t: 'ack', tick: -1 }],
    ['an unknown field', { t: 'ack', tick: 1, extra: 1 }],
    ['a __proto__ key', JSON.parse('{"t":"ack","tick":1,"__proto__":{"x":1}}')],
    ['a constructor key', { t: 'ack', tick: 1, constructor: 1 }],
    ['NaN coordinates', { t: 'input', seq: 1, cmd: { k: 'move', x: Number.NaN, y: 0 } }],
    ['infinite coordinates', { t: 'input', seq: 1, cmd: { k: 'move', x: Number.POSITIVE_INFINITY, y: 0 } }],
    ['an unknown command', { t: 'input', seq: 1, cmd: { k: 'explode' } }],
    [
      'a zero radius',
      { t: 'input', seq: 1, cmd: { k: 'spawn', shape: { type: 'circle', radius: 0 }, x: 0, y: 0 } },
    ],
    [
      'a giant box',
      { t: 'input', seq: 1, cmd: { k: 'spawn', shape: { type: 'box', hw: 1e9, hh: 1 }, x: 0, y: 0 } },
    ],
    [
      'a huge polygon array',
      {
        t: 'input',
        seq: 1,
        cmd: { k: 'spawn', shape: { type: 'polygon', v: new Array(10000).fill(0) }, x: 0, y: 0 },
      },
    ],
    ['a bad room name', { t: 'join', v: PROTOCOL_VERSION, room: '../etc', name: 'x', mode: 'snapshot' }],
    ['a long name', { t: 'join', v: PROTOCOL_VERSION, room: 'a', name: 'x'.repeat(100), mode: 'snapshot' }],
    ['a Date from an extension', { t: 'ack', tick: new Date() }],
    ['gravity beyond the cap', { t: 'input', seq: 1, cmd: { k: 'gravity', x: 0, y: -1e6 } }],
    ['an inspect without a body', { t: 'input', seq: 1, cmd: { k: 'inspect' } }],
    ['an inspect of a negative body', { t: 'input', seq: 1, cmd: { k: 'inspect', body: -1 } }],
    ['an inspect of a fractional body', { t: 'input', seq: 1, cmd: { k: 'inspect', body: 2.5 } }],
    ['an inspect of a NaN body', { t: 'input', seq: 1, cmd: { k: 'inspect', body: Number.NaN } }],
    [
      'an inspect of an infinite body',
      { t: 'input', seq: 1, cmd: { k: 'inspect', body: Number.POSITIVE_INFINITY } },
    ],
    ['an inspect of a body past 2^53', { t: 'input', seq: 1, cmd: { k: 'inspect', body: 2 ** 53 } }],
    [
      'a spawn of density 0 (below 0.05 kg/m^2)',
      {
        t: 'input',
        seq: 1,
        cmd: { k: 'spawn', shape: { type: 'circle', radius: 1 }, x: 0, y: 0, density: 0 },
      },
    ],
    [
      'a spawn of friction 2.5 (above 2)',
      {
        t: 'input',
        seq: 1,
        cmd: { k: 'spawn', shape: { type: 'circle', radius: 1 }, x: 0, y: 0, friction: 2.5 },
      },
    ],
    [
      'a spawn of restitution 1.01 (above 1)',
      {
        t: 'input',
        seq: 1,
        cmd: { k: 'spawn', shape: { type: 'circle', radius: 1 }, x: 0, y: 0, restitution: 1.01 },
      },
    ],
    [
      'a spawn of NaN-like string friction',
      {
        t: 'input',
        seq: 1,
        cmd: { k: 'spawn', shape: { type: 'circle', radius: 1 }, x: 0, y: 0, friction: '0.5' },
      },
    ],
    ['an inspect of a string body', { t: 'input', seq: 1, cmd: { k: 'inspect', body: '3' } }],
    ['an inspect with an extra field', { t: 'input', seq: 1, cmd: { k: 'inspect', body: 3, x: 1 } }],
    ['an inspect with an unknown field', { t: 'input', seq: 1, cmd: { k: 'inspect', body: 3, all: true } }],
  ]
  for (const [what, value] of bad) {
    it(`rejects ${what}`, () => {
      const r = validateClientMessage(value)
      expect(r.ok).toBe(false)
    })
  }

  it('a join with another protocol version is refused naming both versions', () => {
    const r = validateClientMessage({ t: 'join', v: 99, room: 'a', name: 'b', mode: 'snapshot', future: 1 })
    expect(r.ok).toBe(false)
    if (!r.ok) {
      expect(r.code).toBe('version')
      expect(r.reason).toContain('99')
      expect(r.reason).toContain(String(PROTOCOL_VERSION))
    }
  })

  it('deeply nested arrays and msgpackr extensions are rejections, not crashes', () => {
    expect(decodeClientMessage(new Uint8Array(4000).fill(0x91)).ok).toBe(false)
    // A timestamp extension (-1) where a tick belongs.
    const withDate = new Uint8Array([
      0x82, 0xa1, 0x74, 0xa3, 0x61, 0x63, 0x6b, 0xa4, 0x74, 0x69, 0x63, 0x6b, 0xd6, 0xff, 0, 0, 0, 1,
    ])
    expect(decodeClientMessage(withDate).ok).toBe(false)
  })

  it('malformed MessagePack is a rejection, not an exception', () => {
    for (const bytes of [[], [0xc1], [0x92, 0x01], [0xdd, 0xff, 0xff, 0xff, 0xff], [0xd9, 0x40, 0x41]]) {
      const r = decodeClientMessage(new Uint8Array(bytes))
      expect(r.ok).toBe(false)
    }
  })

  it('control characters are stripped from player names', () => {
    const r = validateClientMessage({
      t: 'join',
      v: PROTOCOL_VERSION,
      room: 'a',
      name: 'a\u0000b\u001bc',
      mode: 'snapshot',
    })
    expect(r.ok && r.value.t === 'join' && r.value.name).toBe('abc')
  })
})

describe('spawn material', () => {
  it('accepts density, friction and restitution at the ends of their ranges and keeps them', () => {
    const cmd = {
      k: 'spawn',
      shape: { type: 'circle', radius: 1 },
      x: 0,
      y: 0,
      density: 0.05,
      friction: 2,
      restitution: 1,
    }
    const r = validateClientMessage({ t: 'input', seq: 1, cmd })
    expect(r.ok && r.value).toEqual({ t: 'input', seq: 1, cmd })
  })
})
