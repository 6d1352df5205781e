/*
 * The ground every scene stands on, in its own file so that scene files beside scenes.ts (the
 * machines scene) can use it while scenes.ts lists them in SCENES, without an import cycle.
 */
import { box } from '../collision/index.ts'
import type { BodyDef } from '../types.ts'

/** Ground: a static box whose top surface is y = 0, 200 m wide. */
export function groundDef(halfWidth = 100): BodyDef {
  return { type: 'static', position: { x: 0, y: -1 }, shape: box(halfWidth, 1), friction: 0.6 }
}
