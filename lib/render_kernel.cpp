// SPDX-License-Identifier: MIT
// The renderer's integrand on batches of Gauss points (render_kernel.hpp), compiled once per
// target (AVX-512, AVX2, EMU128) through hwy/foreach_target.h and dispatched at run time.
// Double lanes throughout: the closed-form tests hold the bin energies to 1e-6, and float's
// 6e-8 per operation grows through r^-5 and exp(-kappa r - gauss_coef off^2) (exponents of
// ~10) to a few 1e-6 (docs/physics.md §2.1).
#include "sonarsynth/render_kernel.hpp"

#include <limits>

// clang-format off
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "lib/render_kernel.cpp"
#include <hwy/foreach_target.h>
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>
// clang-format on

HWY_BEFORE_NAMESPACE();
namespace sonarsynth::render_kernel::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// atan2(y, x) from Highway's atan on [0, 1] (3 ulp): the octant by comparisons, one division.
template <class D, class V>
HWY_INLINE V atan2(D d, V y, V x) {
  const V ax = hn::Abs(x), ay = hn::Abs(y);
  const auto steep = hn::Gt(ay, ax);
  const V num = hn::IfThenElse(steep, ax, ay);
  V den = hn::IfThenElse(steep, ay, ax);
  den = hn::IfThenElse(hn::Eq(den, hn::Zero(d)), hn::Set(d, 1.0), den);  // origin: atan(0)
  V a = hn::Atan(d, hn::Div(num, den));                                  // [0, pi/4]
  a = hn::IfThenElse(steep, hn::Sub(hn::Set(d, 1.57079632679489661923), a), a);
  a = hn::IfThenElse(hn::Lt(x, hn::Zero(d)), hn::Sub(hn::Set(d, 3.14159265358979323846), a), a);
  return hn::CopySign(a, y);
}

// cos(pi/2 u) for |u| < 1 as sin(pi/2 (1 - |u|)) by its Taylor series to t^21
// (render_math::sin_series_half_pi, the same terms), 0 for |u| >= 1.
template <class D, class V>
HWY_INLINE V paper_lobe(D d, V u) {
  const V au = hn::Abs(u);
  const V t = hn::Mul(hn::Set(d, 1.57079632679489661923), hn::Sub(hn::Set(d, 1.0), au));
  const V z = hn::Mul(t, t);
  const V z2 = hn::Mul(z, z);
  const V z4 = hn::Mul(z2, z2);
  const V z8 = hn::Mul(z4, z4);
  const V q0 = hn::MulAdd(z, hn::Set(d, 1.0 / 120.0), hn::Set(d, -1.0 / 6.0));
  const V q1 = hn::MulAdd(z, hn::Set(d, 1.0 / 362880.0), hn::Set(d, -1.0 / 5040.0));
  const V q2 = hn::MulAdd(z, hn::Set(d, 1.0 / 6227020800.0), hn::Set(d, -1.0 / 39916800.0));
  const V q3 =
      hn::MulAdd(z, hn::Set(d, 1.0 / 355687428096000.0), hn::Set(d, -1.0 / 1307674368000.0));
  const V q4 = hn::MulAdd(z, hn::Set(d, 1.0 / 51090942171709440000.0),
                          hn::Set(d, -1.0 / 121645100408832000.0));
  const V r0 = hn::MulAdd(z2, q1, q0);
  const V r1 = hn::MulAdd(z2, q3, q2);
  const V p = hn::MulAdd(z8, q4, hn::MulAdd(z4, r1, r0));
  const V s = hn::MulAdd(t, hn::Mul(z, p), t);
  return hn::IfThenZeroElse(hn::Ge(au, hn::Set(d, 1.0)), s);
}

// Coefficients (-1)^k / (2k + 1) of the atan series (render_math::kAtanCoef).
constexpr double atan_coef[8] = {1.0,       -1.0 / 3.0,  1.0 / 5.0,  -1.0 / 7.0,
                                 1.0 / 9.0, -1.0 / 11.0, 1.0 / 13.0, -1.0 / 15.0};

// The bin edge j dr, or the split grid's: k dr for j = 2k, (k + 1) dr - f for j = 2k + 1 (the
// operations of render_facet's grids, so the same doubles).
template <class D, class V>
HWY_INLINE V bin_edge(D d, V j, const PieceArgs& a) {
  const V dr = hn::Set(d, a.dr);
  if (!(a.split_f > 0.0)) return hn::Mul(j, dr);
  const V k = hn::Floor(hn::Mul(j, hn::Set(d, 0.5)));
  const auto odd = hn::Gt(j, hn::Add(k, k));
  return hn::IfThenElse(odd,
                        hn::Sub(hn::Mul(hn::Add(k, hn::Set(d, 1.0)), dr), hn::Set(d, a.split_f)),
                        hn::Mul(k, dr));
}

// render_bins; kFast: the default set-up (2-point rule, spreading, Gaussian beam, the atan
// series on the facet), its tests folded at compile time and its points unrolled.
template <bool kFast>
HWY_INLINE std::size_t bins(const PieceArgs& a, std::ptrdiff_t j_lo, std::ptrdiff_t j_hi,
                            double* HWY_RESTRICT energy, double* HWY_RESTRICT e_out,
                            double* HWY_RESTRICT my_out, double* HWY_RESTRICT mz_out,
                            double* HWY_RESTRICT lo_out, double* HWY_RESTRICT hi_out) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const auto lanes = static_cast<std::ptrdiff_t>(hn::Lanes(d));
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0);
  const V s0 = hn::Set(d, a.s0), s1 = hn::Set(d, a.s1), r1 = hn::Set(d, a.r1);
  const V tm0 = hn::Set(d, a.tm0), p2 = hn::Set(d, a.p2), inv_a = hn::Set(d, a.inv_a);
  const V branch = hn::Set(d, a.branch);
  const V ay = hn::Set(d, a.ay), az = hn::Set(d, a.az_rel);
  const V uy = hn::Set(d, a.uy), uz = hn::Set(d, a.uz);
  const V len = hn::Set(d, a.len_m), coef = hn::Set(d, a.coef);
  const V lim2 = hn::Set(d, a.max_piece_over_range * a.max_piece_over_range);
  const V axis = hn::Set(d, a.axis_rad), gc = hn::Set(d, a.gauss_coef);
  const V kappa = hn::Set(d, a.kappa_per_m);
  const V upper = hn::Set(d, a.paper_upper_rad), lower = hn::Set(d, a.paper_lower_rad);
  const V j_s0 = hn::Set(d, static_cast<double>(a.j_s0));
  const bool gauss = kFast || a.gauss_coef > 0.0;
  const bool paper = !kFast && a.paper;
  const bool angle = gauss || paper;
  const bool spreading = kFast || a.spreading;
  const bool expo_on = gauss || a.kappa_per_m > 0.0;
  const bool rising = a.branch > 0.0;
  const bool series = kFast || (angle && a.series_terms > 0);
  const int points = kFast ? 2 : a.gauss_points;
  const V theta_off = hn::Set(d, a.theta_off), cross = hn::Set(d, a.cross);
  const V w2 = hn::Set(d, a.w2), wu = hn::Set(d, a.wu);
  // Facet::root clamped to the piece.
  const auto root = [&](V edge) {
    const V q = hn::Mul(hn::Sub(hn::Mul(edge, edge), p2), inv_a);
    return hn::Min(hn::Max(hn::Add(tm0, hn::Mul(branch, hn::Sqrt(hn::Max(zero, q)))), s0), s1);
  };
  std::size_t left = 0;
  for (std::ptrdiff_t j0 = j_lo; j0 <= j_hi; j0 += lanes) {
    const std::size_t k = static_cast<std::size_t>(j0 - j_lo);
    const auto in_piece = hn::FirstN(d, static_cast<std::size_t>(j_hi - j0 + 1));
    const V j = hn::Iota(d, static_cast<double>(j0));
    const V e_lo = bin_edge(d, j, a), e_hi = bin_edge(d, hn::Add(j, one), a);
    V lo, hi;
    if (rising) {  // t runs up the bins: [root(lower edge), root(upper edge)]
      lo = hn::IfThenElse(hn::Eq(j, j_s0), s0, root(e_lo));
      hi = hn::IfThenElse(hn::Ge(e_hi, r1), s1, root(e_hi));
    } else {  // t runs down the bins: [root(upper edge), root(lower edge)]
      lo = hn::IfThenElse(hn::Eq(j, j_s0), s0, root(e_hi));
      hi = hn::IfThenElse(hn::Or(hn::Le(e_lo, r1), hn::Eq(j, zero)), s1, root(e_lo));
    }
    const V dq = hn::Sub(hi, lo);
    const auto nonempty = hn::And(in_piece, hn::Gt(dq, zero));
    const V dl = hn::Mul(dq, len);
    const V tmid = hn::Mul(hn::Set(d, 0.5), hn::Add(lo, hi));
    const V my = hn::MulAdd(tmid, uy, ay), mz = hn::MulAdd(tmid, uz, az);
    const V rmid2 = hn::MulAdd(my, my, hn::Mul(mz, mz));
    const auto too_long = hn::And(nonempty, hn::Not(hn::Le(hn::Mul(dl, dl), hn::Mul(lim2, rmid2))));
    V sum = zero;
    for (int g = 0; g < points; ++g) {
      const V t = hn::MulAdd(hn::Set(d, a.gauss_x[g]), dq, lo);
      const V py = hn::MulAdd(t, uy, ay), dz = hn::MulAdd(t, uz, az);
      const V r2 = hn::MulAdd(py, py, hn::Mul(dz, dz));
      const auto at_sensor = hn::Not(hn::Gt(r2, zero));
      const V safe_r2 = hn::IfThenElse(at_sensor, one, r2);
      const V r = hn::Sqrt(safe_r2);
      const V den = spreading ? hn::Mul(hn::Mul(safe_r2, safe_r2), r) : r;
      V val, off = zero;
      if (series) {
        // One division for both quotients: 1 / (den den_x).
        const V den_x = hn::MulAdd(t, wu, w2);
        const V inv = hn::Div(one, hn::Mul(den, den_x));
        val = hn::Mul(hn::Mul(hn::Set(d, a.gauss_w[g]), den_x), inv);
        const V x = hn::Mul(hn::Mul(hn::Mul(t, cross), den), inv);
        const V x2 = hn::Mul(x, x);
        V poly = hn::Set(d, atan_coef[a.series_terms - 1]);
        for (int c = a.series_terms - 2; c >= 0; --c) {
          poly = hn::MulAdd(poly, x2, hn::Set(d, atan_coef[c]));
        }
        off = hn::NegMulAdd(x, poly, theta_off);
      } else {
        val = hn::Div(hn::Set(d, a.gauss_w[g]), den);
        if (angle) off = hn::Sub(atan2(d, hn::Neg(dz), py), axis);
      }
      V expo = zero;
      if (angle) {
        if (gauss) {
          expo = hn::Neg(hn::Mul(hn::Mul(gc, off), off));
        } else {
          const V u = hn::Div(off, hn::IfThenElse(hn::Lt(off, zero), upper, lower));
          const V b = paper_lobe(d, u);
          val = hn::Mul(val, hn::Mul(b, b));
        }
      }
      if (a.kappa_per_m > 0.0) expo = hn::NegMulAdd(kappa, r, expo);
      if (expo_on) val = hn::Mul(val, hn::Exp(d, expo));
      sum = hn::Add(sum, hn::IfThenZeroElse(at_sensor, val));
    }
    const auto done = hn::AndNot(too_long, nonempty);
    const V e = hn::IfThenElseZero(done, hn::Mul(hn::Mul(sum, dl), coef));
    double* const row = energy + j0;
    hn::BlendedStore(hn::Add(hn::MaskedLoad(in_piece, d, row), e), in_piece, d, row);
    hn::StoreU(hn::IfThenElse(too_long, hn::Set(d, std::numeric_limits<double>::quiet_NaN()), e), d,
               e_out + k);
    hn::StoreU(my, d, my_out + k);
    hn::StoreU(mz, d, mz_out + k);
    if (!hn::AllFalse(d, too_long)) {
      hn::StoreU(lo, d, lo_out + k);
      hn::StoreU(hi, d, hi_out + k);
      left += hn::CountTrue(d, too_long);
    }
  }
  return left;
}

std::size_t render_bins(const PieceArgs& a, std::ptrdiff_t j_lo, std::ptrdiff_t j_hi,
                        double* HWY_RESTRICT energy, double* HWY_RESTRICT e_out,
                        double* HWY_RESTRICT my_out, double* HWY_RESTRICT mz_out,
                        double* HWY_RESTRICT lo_out, double* HWY_RESTRICT hi_out) {
  if (a.gauss_points == 2 && a.spreading && a.gauss_coef > 0.0 && !a.paper && a.series_terms > 0) {
    return bins<true>(a, j_lo, j_hi, energy, e_out, my_out, mz_out, lo_out, hi_out);
  }
  return bins<false>(a, j_lo, j_hi, energy, e_out, my_out, mz_out, lo_out, hi_out);
}

void grazing_angles(const double* HWY_RESTRICT y, const double* HWY_RESTRICT dz,
                    double* HWY_RESTRICT g, std::size_t n) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t lanes = hn::Lanes(d);
  const V zero = hn::Zero(d);
  const V pi = hn::Set(d, 3.14159265358979323846), two_pi = hn::Set(d, 6.28318530717958647693);
  const V half_pi = hn::Set(d, 1.57079632679489661923);
  for (std::size_t i = 0; i < n; i += lanes) {
    const auto in = hn::FirstN(d, n - i);
    const V py = hn::MaskedLoad(in, d, y + i), z = hn::MaskedLoad(in, d, dz + i);
    const V alpha = hn::MaskedLoad(in, d, g + i);
    // theta + alpha in (-2 pi, 2 pi]: reduce to (-pi, pi], then fold.
    V a = hn::Add(atan2(d, hn::Neg(z), py), alpha);
    a = hn::IfThenElse(hn::Gt(a, pi), hn::Sub(a, two_pi), a);
    a = hn::IfThenElse(hn::Le(a, hn::Neg(pi)), hn::Add(a, two_pi), a);
    a = hn::IfThenElse(hn::Gt(a, half_pi), hn::Sub(pi, a), a);
    a = hn::IfThenElse(hn::Lt(a, zero), zero, a);
    a = hn::IfThenElseZero(hn::Gt(hn::MulAdd(py, py, hn::Mul(z, z)), zero), a);
    const auto none = hn::IsNaN(alpha);
    hn::BlendedStore(a, hn::AndNot(none, in), d, g + i);
  }
}

}  // namespace sonarsynth::render_kernel::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace sonarsynth::render_kernel {

HWY_EXPORT(render_bins);
HWY_EXPORT(grazing_angles);

void grazing_angles(const double* y, const double* dz, double* g, std::size_t n) {
  HWY_DYNAMIC_DISPATCH(grazing_angles)(y, dz, g, n);
}

std::size_t render_bins(const PieceArgs& a, std::ptrdiff_t j_lo, std::ptrdiff_t j_hi,
                        double* energy, double* e, double* my, double* mz, double* lo, double* hi) {
  return HWY_DYNAMIC_DISPATCH(render_bins)(a, j_lo, j_hi, energy, e, my, mz, lo, hi);
}

}  // namespace sonarsynth::render_kernel
#endif  // HWY_ONCE
