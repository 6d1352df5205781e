/*
 * Per-step values shared by the solver stages. They travel in one object because V8 boxes a double
 * passed to a function it does not inline (a heap allocation per call); a field of a long-lived
 * object is updated in place.
 */
import { ColumnStiffness } from './contact-columns.ts'
import { Softness } from './softness.ts'

/** The solver's per-step scalars. */
export class StepContext {
  /** Sub-step (s) and its inverse (1/s). */
  h = 0.5
  invH = 0.5
  /** Gravity (m/s^2). */
  gravityX = 0.5
  gravityY = 0.5
  /** Fastest overlap push-out (m/s). */
  maxPushSpeed = 0.5
  /** Closing speed below which restitution is ignored (m/s). */
  restitutionThreshold = 0.5
  /** Sleep velocity below which a body rests (m/s; a copy of the setting: see World.finalizeBodies). */
  sleepThreshold = 0.5
  /** Softness and extra sweeps of tall columns' contacts, per column height (contact-columns.ts). */
  readonly columnStiffness = new ColumnStiffness()
  /** Softness of rigid joint constraints (position error correction). */
  readonly jointSoftness = new Softness()
  /** Whether warm starting is on. */
  enableWarmStarting = true
}
