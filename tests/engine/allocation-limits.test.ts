/*
 * Revolute limits and motors allocate nothing once warm: 200 limited pins (half of them with a
 * motor driving into the limit; sleeping off, so every pin is solved every step) step 2,000 times under the allocation test's bound (64 bytes per
 * step, the measuring process's noise floor; tests/engine/allocation.test.ts). The limit solver
 * takes the joint angle from engine/math.ts's atan2 every iteration; a double returned from a call
 * V8 does not inline is a heap allocation, which here would be 16 bytes per pin per iteration
 * (12.8 KB per step), so a bound independent of the pin count is what this checks.
 */
import { dirname } from 'node:path'
import { fileURLToPath } from 'node:url'
import { expect, it } from 'vitest'
import { measureAllocation } from '../support/measure-allocation.ts'

it('200 limited revolute pins with motors step 2,000 times without garbage collection or heap growth', async () => {
  const result = await measureAllocation({
    resolveDir: dirname(fileURLToPath(import.meta.url)),
    setup: `
import { box, createWorld } from '../../engine/index.ts'
const world = createWorld({ gravity: { x: 0, y: -10 }, enableSleep: false })
for (let i = 0; i < 200; i++) {
  const arm = world.createBody({ type: 'dynamic', position: { x: i * 3 + 1, y: 5 }, shape: box(1, 0.1) })
  world.createJoint({
    type: 'revolute', bodyA: null, bodyB: arm, anchor: { x: i * 3, y: 5 },
    enableLimit: true, lower: -0.5, upper: 0.5,
    enableMotor: i % 2 === 0, motorSpeed: 2, maxMotorTorque: 5,
  })
}
for (let i = 0; i < 2000; i++) world.step()
`,
    unit: 'world.step()',
    units: 2000,
    warmup: 0,
    reportAbove: 64,
    timeoutMs: 200_000,
  })
  const perStep = result.heapGrowth / result.units
  console.log(`allocation (revolute limits): ${result.gcCount} collections, ${perStep.toFixed(2)} bytes/step`)
  expect(result.gcCount, JSON.stringify(result.allocators)).toBe(0)
  expect(perStep, JSON.stringify(result.allocators)).toBeLessThan(64)
}, 240_000)
