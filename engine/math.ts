// biome-ignore-all lint/correctness/noPrecisionLoss: fdlibm's published coefficients, kept digit for digit
/*
 * Deterministic math for the engine.
 *
 * ECMAScript specifies `+ - * /` and `Math.sqrt` exactly (IEEE-754 round to nearest), but leaves
 * `Math.sin/cos/atan2/...` to the implementation: V8, SpiderMonkey and JavaScriptCore differ by
 * about one ulp on many inputs. A simulation that must give the same bits everywhere therefore
 * computes its own trigonometry from the exact operations only. The kernels below are the
 * FreeBSD msun (fdlibm) polynomials, accurate to about one ulp, evaluated in a fixed order, so
 * every engine produces identical results.
 *
 * Rotations are stored as a unit (cos, sin) pair; angles only exist at the API boundary.
 */

/** A 2D vector in metres (or m/s, N, ... by context). */
export interface Vec2 {
  x: number
  y: number
}

/** PI to double precision. */
export const PI = Math.PI
/** 2 * PI. */
export const TWO_PI = 2 * Math.PI
/**
 * sin and cos take angles with |x| < TRIG_LIMIT = 2^20 rad, where their argument reduction is
 * exact; beyond it they return NaN, as for a non-finite x (the reduction used to return values
 * such as sin(1e20) = 2.7e27, and NaN at 1e308). The world API refuses such angles.
 */
export const TRIG_LIMIT = 1048576

// fdlibm __kernel_sin coefficients (FreeBSD k_sin.c)
const S1 = -1.66666666666666324348e-1
const S2 = 8.33333333332248946124e-3
const S3 = -1.98412698298579493134e-4
const S4 = 2.75573137070700676789e-6
const S5 = -2.50507602534068634195e-8
const S6 = 1.58969099521155010221e-10

// fdlibm __kernel_cos coefficients (FreeBSD k_cos.c)
const C1 = 4.16666666666666019037e-2
const C2 = -1.38888888888741095749e-3
const C3 = 2.48015872894767294178e-5
const C4 = -2.75573143513906633035e-7
const C5 = 2.0875723212981748279e-9
const C6 = -1.13596475577881948265e-11

// Cody-Waite split of pi/2 (FreeBSD e_rem_pio2.c)
const INV_PIO2 = 6.36619772367581382433e-1
const PIO2_1 = 1.57079632673412561417
const PIO2_2 = 6.0771005063039659766e-11
const PIO2_2T = 2.02226624879595063154e-21
const PIO4 = Math.PI / 4

/** sin on [-pi/4, pi/4] of the double-double x + y. */
function kernelSin(x: number, y: number): number {
  const z = x * x
  const v = z * x
  const r = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)))
  return x - (z * (0.5 * y - v * r) - y - v * S1)
}

/** cos on [-pi/4, pi/4] of the double-double x + y. */
function kernelCos(x: number, y: number): number {
  const z = x * x
  const w = z * z
  const r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6))
  const hz = 0.5 * z
  const t = 1 - hz
  return t + (1 - t - hz + (z * r - x * y))
}

// Reduction output: x = n * pi/2 + (reduced[0] + reduced[1]). A typed array, because a
// module-level `let` holding a double allocates a heap number on every write in V8.
const reduced = new Float64Array(2)

/** Reduces x modulo pi/2; returns the quadrant n (mod 4) and sets `reduced`. */
function reduce(x: number): number {
  const n = Math.round(x * INV_PIO2)
  // Two Cody-Waite iterations: pi/2 is carried to about 118 bits, plenty for |x| < 2^20.
  // (pi/2 = PIO2_1 + PIO2_2 + PIO2_2T; PIO2_1 and PIO2_2 have 33 bits, so n * PIO2_1 is exact.)
  const t = x - n * PIO2_1
  const w2 = n * PIO2_2
  const r2 = t - w2
  const w3 = n * PIO2_2T - (t - r2 - w2)
  const hi = r2 - w3
  reduced[0] = hi
  reduced[1] = r2 - hi - w3
  return ((n % 4) + 4) % 4
}

/** Deterministic sine (radians), within about 1 ulp of the true value for |x| < 2^20; NaN beyond (TRIG_LIMIT). */
export function sin(x: number): number {
  if (!(x > -TRIG_LIMIT && x < TRIG_LIMIT)) return Number.NaN
  if (x > -PIO4 && x < PIO4) return kernelSin(x, 0)
  switch (reduce(x)) {
    case 0:
      return kernelSin(reduced[0], reduced[1])
    case 1:
      return kernelCos(reduced[0], reduced[1])
    case 2:
      return -kernelSin(reduced[0], reduced[1])
    default:
      return -kernelCos(reduced[0], reduced[1])
  }
}

/** Deterministic cosine (radians), within about 1 ulp of the true value for |x| < 2^20; NaN beyond (TRIG_LIMIT). */
export function cos(x: number): number {
  if (!(x > -TRIG_LIMIT && x < TRIG_LIMIT)) return Number.NaN
  if (x > -PIO4 && x < PIO4) return kernelCos(x, 0)
  switch (reduce(x)) {
    case 0:
      return kernelCos(reduced[0], reduced[1])
    case 1:
      return -kernelSin(reduced[0], reduced[1])
    case 2:
      return -kernelCos(reduced[0], reduced[1])
    default:
      return kernelSin(reduced[0], reduced[1])
  }
}

// fdlibm atan tables (FreeBSD s_atan.c)
const ATAN_HI = [
  4.63647609000806093515e-1, 7.85398163397448278999e-1, 9.82793723247329054082e-1, 1.570796326794896558,
]
const ATAN_LO = [
  2.26987774529616870924e-17, 3.06161699786838301793e-17, 1.39033110312309984516e-17,
  6.12323399573676603587e-17,
]
const AT0 = 3.33333333333329318027e-1
const AT1 = -1.99999999998764832476e-1
const AT2 = 1.42857142725034663711e-1
const AT3 = -1.1111110405462355788e-1
const AT4 = 9.09088713343650656196e-2
const AT5 = -7.69187620504482999495e-2
const AT6 = 6.66107313738753120669e-2
const AT7 = -5.83357013379057348645e-2
const AT8 = 4.97687799461593236017e-2
const AT9 = -3.6531572744216915527e-2
const AT10 = 1.62858201153657823623e-2

/** Deterministic arctangent of x >= 0 (radians). */
function atanPositive(x: number): number {
  if (x > 7.37e19) return ATAN_HI[3] + ATAN_LO[3]
  let id: number
  if (x < 0.4375) {
    id = -1
  } else if (x < 1.1875) {
    if (x < 0.6875) {
      id = 0
      x = (2 * x - 1) / (2 + x)
    } else {
      id = 1
      x = (x - 1) / (x + 1)
    }
  } else if (x < 2.4375) {
    id = 2
    x = (x - 1.5) / (1 + 1.5 * x)
  } else {
    id = 3
    x = -1 / x
  }
  const z = x * x
  const w = z * z
  const s1 = z * (AT0 + w * (AT2 + w * (AT4 + w * (AT6 + w * (AT8 + w * AT10)))))
  const s2 = w * (AT1 + w * (AT3 + w * (AT5 + w * (AT7 + w * AT9))))
  if (id < 0) return x - x * (s1 + s2)
  return ATAN_HI[id] - (x * (s1 + s2) - ATAN_LO[id] - x)
}

/** Deterministic arctangent (radians). */
export function atan(x: number): number {
  if (Number.isNaN(x)) return Number.NaN
  return x < 0 ? -atanPositive(-x) : atanPositive(x)
}

const PI_LO = 1.2246467991473531772e-16

/** Deterministic atan2(y, x) in [-pi, pi] (radians), following fdlibm's quadrant rules. */
export function atan2(y: number, x: number): number {
  if (Number.isNaN(x) || Number.isNaN(y)) return Number.NaN
  if (y === 0) {
    if (x > 0 || Object.is(x, 0)) return y
    return Object.is(y, -0) ? -PI : PI
  }
  if (x === 0) return y > 0 ? PI / 2 : -PI / 2
  if (!Number.isFinite(x) || !Number.isFinite(y)) {
    if (!Number.isFinite(x) && !Number.isFinite(y)) {
      const q = x > 0 ? PIO4 : 3 * PIO4
      return y > 0 ? q : -q
    }
    if (!Number.isFinite(y)) return y > 0 ? PI / 2 : -PI / 2
    if (x > 0) return y > 0 ? 0 : -0
    return y > 0 ? PI : -PI
  }
  const z = atanPositive(Math.abs(y / x))
  if (x > 0) return y > 0 ? z : -z
  return y > 0 ? PI - (z - PI_LO) : z - PI_LO - PI
}

/**
 * atan2 without a call that allocates: `io[0] = atan2(io[0], io[1])` (y in io[0], x in io[1]), the
 * same arithmetic as atan2 above with atanPositive written out, so the result is bit-identical
 * (tests/engine/math.test.ts compares them). V8 does not inline atan2 into the joint solvers, and a
 * double passed to or returned from a call it does not inline is a heap allocation: the revolute
 * limit solver needs a joint's angle per joint per iteration (16 bytes each before this).
 */
export function atan2InPlace(io: Float64Array): void {
  const y = io[0]
  const x = io[1]
  if (Number.isNaN(x) || Number.isNaN(y)) {
    io[0] = Number.NaN
    return
  }
  if (y === 0) {
    io[0] = x > 0 || Object.is(x, 0) ? y : Object.is(y, -0) ? -PI : PI
    return
  }
  if (x === 0) {
    io[0] = y > 0 ? PI / 2 : -PI / 2
    return
  }
  if (!Number.isFinite(x) || !Number.isFinite(y)) {
    io[0] = atan2(y, x) // infinities: never in a solver; the plain function's answer
    return
  }
  // atanPositive(|y / x|), written out.
  let t = Math.abs(y / x)
  let z: number
  if (t > 7.37e19) z = ATAN_HI[3] + ATAN_LO[3]
  else {
    let id: number
    if (t < 0.4375) {
      id = -1
    } else if (t < 1.1875) {
      if (t < 0.6875) {
        id = 0
        t = (2 * t - 1) / (2 + t)
      } else {
        id = 1
        t = (t - 1) / (t + 1)
      }
    } else if (t < 2.4375) {
      id = 2
      t = (t - 1.5) / (1 + 1.5 * t)
    } else {
      id = 3
      t = -1 / t
    }
    const zz = t * t
    const w = zz * zz
    const s1 = zz * (AT0 + w * (AT2 + w * (AT4 + w * (AT6 + w * (AT8 + w * AT10)))))
    const s2 = w * (AT1 + w * (AT3 + w * (AT5 + w * (AT7 + w * AT9))))
    z = id < 0 ? t - t * (s1 + s2) : ATAN_HI[id] - (t * (s1 + s2) - ATAN_LO[id] - t)
  }
  if (x > 0) io[0] = y > 0 ? z : -z
  else io[0] = y > 0 ? PI - (z - PI_LO) : z - PI_LO - PI
}

/** Wraps an angle into [-pi, pi]. */
export function wrapAngle(a: number): number {
  if (a >= -PI && a <= PI) return a
  return a - TWO_PI * Math.round(a / TWO_PI)
}
