// SPDX-License-Identifier: MIT
// The numerical kernels of the per-side renderer (lib/render_side.cpp): Gauss–Legendre rules,
// a table exp() and a truncated atan series, scalar and on two SSE2 lanes. Internal.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

// Two Gauss points per SSE2 instruction (GCC/Clang vector extensions; SSE2 is part of the
// x86-64 baseline). Other targets use the scalar path, same formulas.
#if defined(__GNUC__) && defined(__SSE2__)
#include <emmintrin.h>
#define SONARSYNTH_GAUSS_PAIRS 1
#endif

namespace sonarsynth::render_math {

// std::floor without the library call the x86-64 baseline makes of it (no SSE4.1 rounding
// instruction): truncation, moved down for negative non-integers. Equal to std::floor for every
// double (std::floor itself where |x| >= 2^52, infinities and NaN).
inline double floor_fast(double x) {
  if (!(std::abs(x) < 0x1p52)) return std::floor(x);
  const auto t = static_cast<double>(static_cast<std::int64_t>(x));
  if (t > x) return t - 1.0;
  return t == x ? x : t;  // an integer is its own floor (and -0.0 stays -0.0)
}

// cos(pi/2 * x) for |x| <= 1, as sin(pi/2 * y) with y = 1 - |x| (exact for |x| >= 1/2), by its
// Taylor series to t^21: the first term left out, (pi/2)^23 / 23!, is 1.3e-18 of the result at
// most, so the error is the few roundings of the evaluation (within 4e-16 relative of a long
// double reference everywhere, the zero at |x| = 1 included; tests/render_side_test.cpp).
// glibc's cos() reduces the argument and switches the rounding mode on every call: the vertical
// beam pattern evaluates this at every Gauss point of the renderer.
constexpr double kHalfPi = 1.57079632679489661923;
// sin(t) for |t| <= pi/2 by the series above; on doubles or on two lanes (the same operations
// lane by lane). The polynomial in t^2 by Estrin's scheme: pairs of terms combined with t^2,
// t^4 and t^8, a chain of 6 dependent operations where Horner's rule has 20 (the renderer's
// Gauss points wait on it); the same terms, rounded in a different order.
template <class T>
[[gnu::always_inline]] inline T sin_series_half_pi(T t) {
  const T z = t * t;
  const T z2 = z * z;
  const T z4 = z2 * z2;
  const T z8 = z4 * z4;
  // 1/(2k+1)! with alternating signs, k = 1 to 10: c1 + c2 z + ... + c10 z^9.
  const T q0 = z * (1.0 / 120.0) - 1.0 / 6.0;
  const T q1 = z * (1.0 / 362880.0) - 1.0 / 5040.0;
  const T q2 = z * (1.0 / 6227020800.0) - 1.0 / 39916800.0;
  const T q3 = z * (1.0 / 355687428096000.0) - 1.0 / 1307674368000.0;
  const T q4 = z * (1.0 / 51090942171709440000.0) - 1.0 / 121645100408832000.0;
  const T r0 = q0 + z2 * q1;
  const T r1 = q2 + z2 * q3;
  const T p = (r0 + z4 * r1) + z8 * q4;
  return t + t * (z * p);
}
inline double cos_half_pi(double x) {
  return sin_series_half_pi(kHalfPi * (1.0 - std::abs(x)));
}
// The founding paper's vertical beam, one way: cos(pi/2 off / w), w the half-width above
// (off < 0) or below the axis, 0 beyond it (VerticalBeamShape::paper_sine_pair; the renderer's
// two-lane gauss_pair evaluates the same operations lane by lane).
inline double paper_sine_pair(double off_rad, double upper_half_width_rad,
                              double lower_half_width_rad) {
  const double x = off_rad / (off_rad < 0.0 ? upper_half_width_rad : lower_half_width_rad);
  return std::abs(x) >= 1.0 ? 0.0 : cos_half_pi(x);
}

// Gauss–Legendre rules mapped to [0, 1] (Abramowitz & Stegun, Table 25.4).
struct GaussRule {
  int n;
  double x[5];
  double w[5];
};
constexpr GaussRule make_rule(int n, const double (&x)[5], const double (&w)[5]) {
  GaussRule r{n, {}, {}};
  for (int i = 0; i < n; ++i) {
    r.x[i] = 0.5 * (1.0 + x[i]);
    r.w[i] = 0.5 * w[i];
  }
  return r;
}
constexpr GaussRule kRules[5] = {
    make_rule(1, {0, 0, 0, 0, 0}, {2, 0, 0, 0, 0}),
    make_rule(2, {-0.57735026918962576451, 0.57735026918962576451, 0, 0, 0}, {1, 1, 0, 0, 0}),
    make_rule(3, {-0.77459666924148337704, 0, 0.77459666924148337704, 0, 0},
              {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0, 0, 0}),
    make_rule(4,
              {-0.86113631159405257522, -0.33998104358485626480, 0.33998104358485626480,
               0.86113631159405257522, 0},
              {0.34785484513745385737, 0.65214515486254614263, 0.65214515486254614263,
               0.34785484513745385737, 0}),
    make_rule(5,
              {-0.90617984593866399280, -0.53846931010568309104, 0, 0.53846931010568309104,
               0.90617984593866399280},
              {0.23692688505618908751, 0.47862867049936646804, 0.56888888888888888889,
               0.47862867049936646804, 0.23692688505618908751}),
};

// exp(x) without a libm call (Tang's table method, ACM TOMS 15(2):144-157, 1989): x = (64 m +
// j) ln2 / 64 + r with |r| <= ln2 / 128, exp(x) = 2^m 2^(j/64) exp(r), exp(r) by its Taylor
// polynomial to r^5 (first omitted term < 0.0055^6 / 720 < 4e-17): a few ulp, against ~1e-6
// needed. k = 64 m + j = nearest integer to 64 x / ln2 by the round-to-nearest shifter 1.5 2^52
// (its low mantissa bits hold k); ln2 / 64 is split in a 32-bit head (k ln2_hi exact for
// |k| < 2^21) and a tail; 2^m is added to the exponent field of the table entry 2^(j/64).
struct Exp2Table {
  std::uint64_t bits[64];
  Exp2Table() {
    for (int j = 0; j < 64; ++j) {
      bits[j] = std::bit_cast<std::uint64_t>(std::exp2(static_cast<double>(j) / 64.0));
    }
  }
};
inline const Exp2Table kExp2Table;

inline double exp_table(double x) {
  if (!(x > -700.0 && x < 700.0)) return std::exp(x);                 // far tails, NaN: libm
  constexpr double kInvLn2x64 = 92.332482616893656877;                // 64 / ln 2
  constexpr double kLn2HiOver64 = 6.93147180369123816490e-01 / 64.0;  // fdlibm ln2_hi / 64
  constexpr double kLn2LoOver64 = 1.90821492927058770002e-10 / 64.0;  // fdlibm ln2_lo / 64
  constexpr double kShifter = 0x1.8p52;
  const double shifted = x * kInvLn2x64 + kShifter;
  const std::uint64_t k = std::bit_cast<std::uint64_t>(shifted);  // low bits: k mod 2^51
  const double kd = shifted - kShifter;                           // k, exactly
  const double r = (x - kd * kLn2HiOver64) - kd * kLn2LoOver64;
  const double p =
      1.0 + r * (1.0 + r * (0.5 + r * (1.0 / 6.0 + r * (1.0 / 24.0 + r * (1.0 / 120.0)))));
  // m = floor(k / 64) in the exponent field: (k >> 6) << 52 modulo 2^64 (k < 0 wraps, |m| < 1100).
  const std::uint64_t scaled = kExp2Table.bits[k & 63] + ((k >> 6) << 52);
  return std::bit_cast<double>(scaled) * p;
}

#ifdef SONARSYNTH_GAUSS_PAIRS
using V2d = double __attribute__((vector_size(16)));
using V2u = std::uint64_t __attribute__((vector_size(16)));

inline V2d sqrt2(V2d x) {
  return reinterpret_cast<V2d>(_mm_sqrt_pd(reinterpret_cast<__m128d>(x)));
}

// exp_table on two lanes: the same operations lane by lane (bit-identical results), only the
// table look-up is scalar.
[[gnu::always_inline]] inline V2d exp_table2(V2d x) {
  // Both lanes in range (NaN compares false): SSE2 compares and one movemask (the vector
  // extension's lane masks were normalised lane by lane before the test).
  const __m128d xv = reinterpret_cast<__m128d>(x);
  const __m128d ok =
      _mm_and_pd(_mm_cmpgt_pd(xv, _mm_set1_pd(-700.0)), _mm_cmplt_pd(xv, _mm_set1_pd(700.0)));
  if (_mm_movemask_pd(ok) != 3) {
    return V2d{exp_table(x[0]), exp_table(x[1])};
  }
  constexpr double kInvLn2x64 = 92.332482616893656877;
  constexpr double kLn2HiOver64 = 6.93147180369123816490e-01 / 64.0;
  constexpr double kLn2LoOver64 = 1.90821492927058770002e-10 / 64.0;
  constexpr double kShifter = 0x1.8p52;
  const V2d shifted = x * kInvLn2x64 + kShifter;
  const V2u k = reinterpret_cast<V2u>(shifted);
  const V2d kd = shifted - kShifter;
  const V2d r = (x - kd * kLn2HiOver64) - kd * kLn2LoOver64;
  const V2d p =
      1.0 + r * (1.0 + r * (0.5 + r * (1.0 / 6.0 + r * (1.0 / 24.0 + r * (1.0 / 120.0)))));
  const V2u table{kExp2Table.bits[k[0] & 63], kExp2Table.bits[k[1] & 63]};
  const V2u scaled = table + ((k >> 6) << 52);
  return reinterpret_cast<V2d>(scaled) * p;
}
#endif

// Coefficients (-1)^k / (2k + 1) of the atan series.
constexpr double kAtanCoef[8] = {1.0,       -1.0 / 3.0,  1.0 / 5.0,  -1.0 / 7.0,
                                 1.0 / 9.0, -1.0 / 11.0, 1.0 / 13.0, -1.0 / 15.0};
// Bound on the first omitted term of the truncated atan series (absolute error in radians).
constexpr double kAtanTolerance = 1e-18;

// Terms of the atan series x - x^3/3 + ... (alternating, decreasing for |x| < 1: the error is
// below the first omitted term |x|^(2n+1) / (2n+1)) needed for |x| <= x_max, 1 .. 8.
inline int atan_terms(double x_max) {
  double pow = x_max * x_max * x_max;  // x^(2n+1) for n = 1
  for (int n = 1; n < 8; ++n) {
    if (pow / static_cast<double>(2 * n + 1) < kAtanTolerance) return n;
    pow *= x_max * x_max;
  }
  return 8;
}

// p(x2) = sum_{k < n} c_k x2^k by Horner, n in 1 .. 8 (cases fall through: case m adds c_{m-2}).
template <class T>
inline T atan_poly(T x2, int n) {
  T p = T{} + kAtanCoef[n - 1];
  switch (n) {
    case 8:
      p = p * x2 + kAtanCoef[6];
      [[fallthrough]];
    case 7:
      p = p * x2 + kAtanCoef[5];
      [[fallthrough]];
    case 6:
      p = p * x2 + kAtanCoef[4];
      [[fallthrough]];
    case 5:
      p = p * x2 + kAtanCoef[3];
      [[fallthrough]];
    case 4:
      p = p * x2 + kAtanCoef[2];
      [[fallthrough]];
    case 3:
      p = p * x2 + kAtanCoef[1];
      [[fallthrough]];
    case 2:
      p = p * x2 + kAtanCoef[0];
      [[fallthrough]];
    default:
      break;
  }
  return p;
}

}  // namespace sonarsynth::render_math
