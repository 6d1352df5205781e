/*
 * King of the hill's constants (index.ts has the rules). Seen from above: gravity 0, a square
 * arena with walls, the hill a circular sensor in its middle.
 */

/** Half the arena's side (m): the walls' inner faces are at x, y = +-ARENA. */
export const ARENA = 8
/** The hill: a sensor disc at the origin (m). A puck is on the hill while its disc overlaps it. */
export const HILL_RADIUS = 1.5
/** A puck: radius (m), density (kg/m^2), linear damping (1/s). */
export const PUCK_RADIUS = 0.5
export const PUCK_DENSITY = 1
export const PUCK_DAMPING = 1
/** A push at full strength (|(x, y)| = 1) gives the puck this impulse (N s). */
export const PUSH_IMPULSE = 3
/** Ticks between two pushes of one player. */
export const PUSH_COOLDOWN = 10
/** Ticks alone on the hill that win (3 s). */
export const WIN_TICKS = 180
/** Player slots and their starting spots, in slot order. */
export const SPOTS = [
  { x: -6, y: 0 },
  { x: 6, y: 0 },
  { x: 0, y: -6 },
  { x: 0, y: 6 },
] as const
/** Room ticks per second. */
export const TICK_HZ = 60
