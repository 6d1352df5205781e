/*
 * planck 1.5 declares `engines: node >= 24`, so `npm install` on Node 20 prints an EBADENGINE
 * warning (issue 31, fix 11). The README says it is harmless: planck is a dev dependency that only
 * the peer benchmarks load. This test holds that promise on the Node running the suite (20 in CI):
 * planck loads and steps a falling box exactly as its integrator says it must.
 */
import { readFileSync } from 'node:fs'
import { BoxShape, World } from 'planck'
import { describe, expect, it } from 'vitest'

describe('planck on this Node', () => {
  it('loads and integrates free fall as semi-implicit Euler predicts, whatever its engines field says', () => {
    const manifest = JSON.parse(readFileSync('node_modules/planck/package.json', 'utf8')) as {
      version: string
      engines?: { node?: string }
    }
    // What the README explains: the declared range, and the Node the suite runs on.
    expect(manifest.engines?.node ?? '').toMatch(/^>=\d+/)
    expect(Number(process.versions.node.split('.')[0])).toBeGreaterThanOrEqual(20)

    const world = new World({ gravity: { x: 0, y: -10 } })
    const body = world.createBody({ type: 'dynamic', position: { x: 0, y: 100 } })
    body.createFixture({ shape: new BoxShape(0.5, 0.5), density: 1 })
    const dt = 1 / 60
    for (let n = 1; n <= 60; n++) {
      world.step(dt)
      // Semi-implicit Euler from rest: v_n = -g n dt, y_n = y_0 - g dt^2 n (n + 1) / 2.
      expect(body.getPosition().y).toBeCloseTo(100 - (10 * dt * dt * n * (n + 1)) / 2, 9)
      expect(body.getLinearVelocity().y).toBeCloseTo(-10 * dt * n, 9)
    }
  })
})
