/** Where the launcher shoots from (m). */
export const LAUNCHER = { x: -8, y: 1 } as const
/** The hoop: the centre of its rim (m) and half the rim's opening (m). */
export const HOOP = { x: 4, y: 4, halfWidth: 0.6 } as const
/** Ticks between two shots of one player (0.5 s). */
export const SHOT_INTERVAL_TICKS = 30
/** Ticks a ball lives before it is removed (5 s). */
export const BALL_LIFE_TICKS = 300
