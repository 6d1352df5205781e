/*
 * Per-address limits and IPv6: a subscriber usually holds a whole /64, so counting each IPv6
 * address on its own let one client take a fresh address per connection past
 * --max-connections-per-ip. addressKey against hand-expanded addresses (only ::1 exists on
 * loopback, so the addresses are written out here), then a ConnectionGuard fed sockets that claim
 * such addresses.
 */
import { EventEmitter } from 'node:events'
import type { Server } from 'node:http'
import type { Socket } from 'node:net'
import { Duplex } from 'node:stream'
import pino from 'pino'
import { describe, expect, it } from 'vitest'
import { loadConfig } from '../../../server/config/config.ts'
import { LogLimiter } from '../../../server/hosting/log-limiter.ts'
import { createMetrics } from '../../../server/hosting/metrics.ts'
import { addressKey, ConnectionGuard } from '../../../server/http/http-connections.ts'

describe('addressKey', () => {
  it('keys an IPv6 address by its /64, however it is written', () => {
    // The first four groups, written out by hand for each form.
    const cases: Array<[string, string]> = [
      ['2001:db8:0:1::1', '2001:db8:0:1::/64'],
      ['2001:db8:0:1:ffff:ffff:ffff:fffe', '2001:db8:0:1::/64'],
      ['2001:0DB8:0000:0001:0000:0000:0000:0042', '2001:db8:0:1::/64'],
      ['2001:db8::1', '2001:db8:0:0::/64'],
      ['2001:db8:0:2::1', '2001:db8:0:2::/64'],
      ['fe80::1%eth0', 'fe80:0:0:0::/64'],
      ['fe80::abcd%7', 'fe80:0:0:0::/64'],
      ['::1', '0:0:0:0::/64'],
      ['::', '0:0:0:0::/64'],
      ['1:2:3:4:5:6:7:8', '1:2:3:4::/64'],
      ['1:2:3::8', '1:2:3:0::/64'],
      ['1:2:3:4:5::', '1:2:3:4::/64'],
      // An IPv4 tail on an address that is not IPv4-mapped (NAT64) stays IPv6.
      ['64:ff9b::192.0.2.1', '64:ff9b:0:0::/64'],
    ]
    for (const [address, key] of cases) expect(addressKey(address), address).toBe(key)
  })

  it('keys IPv4 and IPv4-mapped IPv6 by the IPv4 address, and leaves anything else as it is', () => {
    expect(addressKey('203.0.113.7')).toBe('203.0.113.7')
    expect(addressKey('::ffff:203.0.113.7')).toBe('203.0.113.7')
    expect(addressKey('::FFFF:203.0.113.7')).toBe('203.0.113.7')
    expect(addressKey('0:0:0:0:0:ffff:203.0.113.7')).toBe('203.0.113.7')
    // The same mapped address in hex: cb00:7107 = 203.0.113.7.
    expect(addressKey('::ffff:cb00:7107')).toBe('203.0.113.7')
    expect(addressKey('::ffff:1.2.3.4%eth0')).toBe('1.2.3.4')
    expect(addressKey('unknown')).toBe('unknown')
    expect(addressKey('')).toBe('')
  })
})

/** A socket that says it comes from `address` and keeps what is written to it in `written`. */
function socketFrom(address: string): Socket & { written: string } {
  let written = ''
  const socket = new Duplex({
    read() {},
    write: (chunk: Buffer, _encoding, done) => {
      written += chunk.toString('latin1')
      done()
    },
  })
  Object.defineProperty(socket, 'remoteAddress', { value: address })
  Object.defineProperty(socket, 'written', { get: () => written })
  return socket as unknown as Socket & { written: string }
}

describe('the per-address connection cap over IPv6', () => {
  it('counts every address of one /64 together and refuses the one past the cap; another /64 is apart', () => {
    const config = loadConfig([], {}, { maxConnectionsPerIp: 2 })
    const guard = new ConnectionGuard(config, createMetrics(false), new LogLimiter(pino({ level: 'silent' })))
    const http = new EventEmitter()
    guard.attach(http as unknown as Server)
    const sockets = ['2001:db8:0:1::1', '2001:db8:0:1::2', '2001:db8:0:1:ffff::3', '2001:db8:0:2::1'].map(
      (address) => {
        const socket = socketFrom(address)
        http.emit('connection', socket)
        return socket
      },
    )
    expect(sockets.map((s) => s.written.startsWith('HTTP/1.1 429 '))).toEqual([false, false, true, false])
    expect(guard.countOf('2001:db8:0:1::abcd')).toBe(2)
    expect(guard.countOf('2001:db8:0:2::abcd')).toBe(1)
    expect(guard.count).toBe(3)
    for (const s of sockets) s.destroy()
  })
})
