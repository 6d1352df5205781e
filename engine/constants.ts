/*
 * The engine's fixed tolerances and limits, in one place (Box2D v3 keeps them in constants.h and
 * core.h). Settings a world may change (contact stiffness, push-out speed, sleep thresholds) are in
 * DEFAULT_WORLD_DEF instead; these are the values the algorithms are built around.
 */

/** The fixed step (s): 1/60. */
export const STEP_SECONDS = 1 / 60
/** Collision tolerance (m): 0.005, Box2D's b2_linearSlop. Narrowphase tolerances derive from it. */
export const LINEAR_SLOP = 0.005
/** Contacts are created while shapes are closer than this (m): 4 x slop = 0.02 (b2_speculativeDistance). */
export const SPECULATIVE_DISTANCE = 4 * LINEAR_SLOP
/** Fastest linear speed a body may reach (m/s): 400, Box2D v3's maxLinearSpeed (4 m per step at 100 Hz). */
export const MAX_LINEAR_SPEED = 400
/** Largest rotation of a body in one sub-step (rad): a quarter turn over pi, Box2D v3's b2_maxRotation. */
export const MAX_ROTATION = 0.25 * Math.PI
/** Most vertices a convex polygon may have (b2_maxPolygonVertices). */
export const MAX_POLYGON_VERTICES = 8
/** Most points a chain may have (chain()): 2,048. */
export const MAX_CHAIN_POINTS = 2048
/** Smallest radius, half extent or edge a shape may have (m). */
export const MIN_SHAPE_EXTENT = 0.001
/**
 * Largest reach of a shape from its body origin, per axis (m): 100 km, Box2D's B2_HUGE. Beyond
 * about 1e153 m a shape's inertia overflows to Infinity and its body's centre becomes NaN; the
 * bound keeps every product of two lengths, a density and an area far inside the double range.
 */
export const MAX_SHAPE_EXTENT = 1e5
/**
 * Largest |x| or |y| of a position the API sets (m): 1000 km. There doubles still resolve 1.2e-10 m;
 * at 2^53 m they are 2 m apart, so a body moves in jumps larger than a step's speed limit allows.
 * Bodies may still travel past it under the simulation's own motion.
 */
export const MAX_POSITION = 1e6
/** Hit events report contacts that closed faster than this (m/s): 1, Box2D's hitEventThreshold. */
export const HIT_EVENT_SPEED = 1
/** Fat AABBs grow this much around the tight box of a moving body (m), Box2D's b2_aabbMargin. */
export const AABB_MARGIN = 0.1
/** Re-fattened proxies reach this many displacements ahead along the motion (Box2D v2.4's aabbMultiplier). */
export const DISPLACEMENT_MULTIPLIER = 4
/**
 * A dynamic body in contact with a dynamic body more than this many times heavier is "pinched": one
 * Gauss-Seidel sweep moves a heavy body's velocity by only about the light/heavy mass ratio per
 * contact, so its contacts get extra sweeps (see contact-solver.ts).
 */
export const PINCH_MASS_RATIO = 10
/**
 * A shape whose thickness is less than this fraction of its length is "slender" (collision/shapes.ts
 * isSlender): a card, a thin plank, a rod. A slender body standing on its end or leaning stands on a
 * support as wide as its thickness, so a velocity error a compact body shrugs off tips it over (a 2 mm
 * card 0.4 m long tips at 1/200 of what a cube survives); its contacts get extra sweeps like a pinched
 * body's (see contact-solver.ts): 1/20.
 */
export const SLENDER_RATIO = 0.05
/**
 * A slender body stands or leans on an end, and its contacts get the extra sweeps (contact-solver.ts),
 * only through a contact whose normal, and gravity too, lie nearer its long axis than across it:
 * |normal . axis| and |gravity . axis| / |gravity| above cos 45 degrees. A card leaning 25 degrees
 * off upright has 0.91 for both on the ground; a card or plank lying flat, or touching along its
 * long side, about 0 (a flat plank's end touching a neighbour's end has the normal along its axis
 * but gravity across it).
 */
export const SLENDER_END_COSINE = Math.SQRT1_2
/** Extra sweeps over a pinched or slender body's or a column's contacts after each solve and relax sweep. */
export const PINCHED_EXTRA_ITERATIONS = 3
/**
 * Bodies in a chain (each touching only the one below and the one above, on a static body) from which
 * the chain's contacts are solved as a column (contact-columns.ts): 12. A column of 1 m boxes on 45 Hz
 * contacts is past its buckling load at 20 boxes and at 0.28 of it at 12 (tests/engine/README.md "Robustness").
 */
export const COLUMN_MIN_BODIES = 12
/** Columns up to this many bodies are solved at twice contactHertz; taller ones stiffer (contact-columns.ts): 20. */
export const COLUMN_STIFF_BODIES = 20
/**
 * Buckling factor at unit contact stiffness (omega = 1 rad/s, so in (rad/s)^2) of a 20-box column
 * of 1 m boxes as extra-sweeps.ts weighs it (106,384; 12, 30 and 50 boxes: 22,990, 359,264 and
 * 1,664,440, the n^3 law), with 3.4 % margin so that a column of equal 1 m boxes never counts as
 * taller than it is: 110,000 (contact-columns.ts equivalentHeight).
 */
export const COLUMN_REFERENCE_FACTOR = 110000
/** Columns taller than this are solved as this tall (the stiffening stops growing): 50. */
export const COLUMN_MAX_BODIES = 50
/**
 * The extra sweeps of a step (pinched and column contacts) solve at most this many times the step's
 * contacts: 3, so the contact solver costs at most 4 times its one sweep per pass (contact-columns.ts).
 */
export const EXTRA_SWEEP_BUDGET = 3
/** ... or at least this many contact solves per pass: 3,072 (two lone 50-box columns need 2 x 51 x 24 = 2,448). */
export const EXTRA_SWEEP_FLOOR = 3072
