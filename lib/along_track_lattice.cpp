// SPDX-License-Identifier: MIT
// The along-track speckle lattice's kernel (docs/physics.md §1.6): per block of samples, per
// look, the three scatterers nearest the ping — keyed counter-hash words, Box-Muller by
// arithmetic — summed with their weights, in float vectors across samples. Compiled per target
// (AVX-512, AVX2, portable scalar) and chosen at run time (lib/simd.cpp).
#include "sonarsynth/along_track_lattice.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "sonarsynth/simd.hpp"

// clang-format off
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "lib/along_track_lattice.cpp"
#include <hwy/foreach_target.h>
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>
#include "sonarsynth/counter_hash-inl.hpp"
// clang-format on

HWY_BEFORE_NAMESPACE();
namespace sonarsynth::lattice::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace chv = sonarsynth::counter_hash::HWY_NAMESPACE;

// -ln u for normal u in (0, 1): u = 2^e m with m in [sqrt(1/2), sqrt(2)), ln m = t - t^2 / 2 +
// t^3 P(t) (t = m - 1; P of degree 5, fitted to the relative error of ln m by weighted least
// squares on Chebyshev nodes: 2.9e-7 in exact arithmetic), no division.
template <class DF>
HWY_INLINE hn::Vec<DF> NegLog(DF df, hn::Vec<DF> u) {
  const hn::RebindToSigned<DF> di;
  const auto bits = hn::Sub(hn::BitCast(di, u), hn::Set(di, 0x3f3504f3));
  const auto e = hn::ConvertTo(df, hn::ShiftRight<23>(bits));
  const auto m =
      hn::BitCast(df, hn::Add(hn::And(bits, hn::Set(di, 0x007fffff)), hn::Set(di, 0x3f3504f3)));
  const auto t = hn::Sub(m, hn::Set(df, 1.0f));
  auto p = hn::MulAdd(t, hn::Set(df, -0.10069556772595721f), hn::Set(df, 0.15987878618007076f));
  p = hn::MulAdd(t, p, hn::Set(df, -0.17155025783988495f));
  p = hn::MulAdd(t, p, hn::Set(df, 0.19928080159199288f));
  p = hn::MulAdd(t, p, hn::Set(df, -0.2498254786671757f));
  p = hn::MulAdd(t, p, hn::Set(df, 0.33334209555484495f));
  const auto t2 = hn::Mul(t, t);
  const auto lnm = hn::Add(t, hn::MulAdd(hn::Mul(t2, t), p, hn::Mul(t2, hn::Set(df, -0.5f))));
  return hn::NegMulSub(e, hn::Set(df, 0.69314718055994531f), lnm);
}

// The scatterer of look word w, as scatterer_reference: r = sqrt(-ln u1) (NegLog) times
// `scale` = 1 / sqrt(2 mean_neg_log_midpoints()); the phase phi = q pi/2 + pi/4 + x from the word's
// top two bits q and the next 10 (x in (-pi/4, pi/4)); cos and sin of pi/4 + x from Taylor
// polynomials of x (truncation below 3e-8 and 3e-7), then turned by q quarter turns (a swap and
// signs).
template <class DF, class DU>
HWY_INLINE void Scatterer(DF df, DU du, hn::Vec<DU> w, hn::Vec<DF> scale, hn::Vec<DF>& zr,
                          hn::Vec<DF>& zi) {
  const hn::RebindToSigned<DU> di;
  const auto u1 = hn::MulAdd(hn::ConvertTo(df, hn::BitCast(di, hn::And(w, hn::Set(du, 0xfffffU)))),
                             hn::Set(df, 0x1p-20f), hn::Set(df, 0x1p-21f));
  constexpr float kCell = static_cast<float>(1.5707963267948966 * 0x1p-10);
  const auto x = hn::MulAdd(
      hn::ConvertTo(df, hn::BitCast(di, hn::And(hn::ShiftRight<20>(w), hn::Set(du, 0x3ffU)))),
      hn::Set(df, kCell), hn::Set(df, 0.5f * kCell - 0.78539816339744831f));
  const auto x2 = hn::Mul(x, x);
  auto sp = hn::MulAdd(x2, hn::Set(df, -1.0f / 5040.0f), hn::Set(df, 1.0f / 120.0f));
  sp = hn::MulAdd(x2, sp, hn::Set(df, -1.0f / 6.0f));
  const auto sn = hn::MulAdd(hn::Mul(x, x2), sp, x);
  auto cp = hn::MulAdd(x2, hn::Set(df, 1.0f / 40320.0f), hn::Set(df, -1.0f / 720.0f));
  cp = hn::MulAdd(x2, cp, hn::Set(df, 1.0f / 24.0f));
  cp = hn::MulAdd(x2, cp, hn::Set(df, -0.5f));
  const auto cs = hn::MulAdd(x2, cp, hn::Set(df, 1.0f));
  // (cos x - sin x, cos x + sin x) / sqrt(2) = (cos, sin)(pi/4 + x).
  const auto rr = hn::Mul(hn::Sqrt(NegLog(df, u1)), scale);
  const auto c = hn::Mul(hn::Sub(cs, sn), rr);
  const auto sv = hn::Mul(hn::Add(cs, sn), rr);
  // Quarter turns q (bits 31 and 30 of w): (c, s), (-s, c), (-c, -s), (s, -c).
  const auto swap = hn::RebindMask(
      df, hn::MaskFromVec(hn::BroadcastSignBit(hn::BitCast(di, hn::ShiftLeft<1>(w)))));
  const auto sign = hn::Set(du, 0x80000000U);
  const auto a = hn::IfThenElse(swap, sv, c);
  const auto b = hn::IfThenElse(swap, c, sv);
  zr = hn::Xor(a, hn::BitCast(df, hn::And(hn::Xor(w, hn::ShiftLeft<1>(w)), sign)));
  zi = hn::Xor(b, hn::BitCast(df, hn::And(w, sign)));
}

// The geometry of a block (f64 vectors): u = s / (1.5 sw) the ping's position in lattice
// steps; the lattice applies from the first return, where consecutive pings are at most 2.5
// footprints (r beta_eff = 1.77 sw) apart (correlation > 1e-4), where |u| < 1e15 (not a
// degenerate beam or position) and the need is positive. The three scatterers nearest u:
// m0 - 1 .. m0 + 1 below frac = u - m0 = 1/2, else m0 .. m0 + 2 (m0 = floor u; the next carries
// at most 0.55 % of the weight power). Returns the number of samples where it applies.
std::size_t GeometryBlock(const GeometryArgs& a) {
  const hn::ScalableTag<double> dd;
  const hn::Rebind<std::int32_t, decltype(dd)> di;
  const hn::Rebind<std::uint32_t, decltype(dd)> du;
  const hn::Rebind<float, decltype(dd)> df;
  const std::size_t lanes = hn::Lanes(dd);
  Geometry& g = *a.g;
  std::size_t applied = 0;
  const auto along = hn::Set(dd, a.along_track_m);
  const auto spacing = hn::Set(dd, a.ping_spacing_m);
  const auto zero = hn::Zero(dd);
  for (std::size_t t = 0; t < a.n; t += lanes) {
    const auto index = hn::Iota(dd, static_cast<double>(a.i0 + t));
    const auto u = hn::Mul(along, hn::LoadU(dd, a.inv_step + t));
    auto valid =
        hn::And(hn::Ge(index, hn::Set(dd, a.first_sample)), hn::Lt(hn::Abs(u), hn::Set(dd, 1e15)));
    valid = hn::AndNot(hn::Gt(spacing, hn::Mul(hn::Set(dd, 4.43), hn::LoadU(dd, a.sw + t))), valid);
    if (a.need != nullptr) valid = hn::And(valid, hn::Gt(hn::LoadU(dd, a.need + t), zero));
    applied += hn::CountTrue(dd, valid);
    const auto uv = hn::IfThenElseZero(valid, u);
    const auto m0 = hn::Floor(uv);
    const auto first = hn::Sub(
        m0, hn::IfThenElseZero(hn::Lt(hn::Sub(uv, m0), hn::Set(dd, 0.5)), hn::Set(dd, 1.0)));
    const auto d0 = hn::IfThenElse(valid, hn::Sub(first, uv),
                                   hn::Set(dd, std::numeric_limits<double>::quiet_NaN()));
    hn::StoreU(hn::DemoteTo(df, d0), df, g.d0 + t);
    // first = high 2^32 + low, low in [0, 2^32) (|first| < 2^50: exact in double).
    const auto high = hn::Floor(hn::Mul(first, hn::Set(dd, 0x1p-32)));
    const auto low = hn::Sub(first, hn::Mul(high, hn::Set(dd, 0x1p32)));
    const auto lo = hn::Xor(hn::BitCast(du, hn::DemoteTo(di, hn::Sub(low, hn::Set(dd, 0x1p31)))),
                            hn::Set(du, 0x80000000U));
    const auto hi32 = hn::BitCast(du, hn::DemoteTo(di, high));
    const auto index_u = hn::Iota(du, static_cast<std::uint32_t>(a.i0 + t));
    hn::StoreU(lo, du, g.lo + t);
    hn::StoreU(hn::Add(index_u, hn::Mul(hi32, hn::Set(du, kHighMul))), du, g.hi + t);
  }
  return applied;
}

void LatticeBlock(const BlockArgs& a) {
  const hn::ScalableTag<float> df;
  const hn::RebindToUnsigned<decltype(df)> du;
  const hn::RebindToSigned<decltype(df)> di;
  using VF = hn::Vec<decltype(df)>;
  const std::size_t lanes = hn::Lanes(df);
  Geometry& g = *a.g;
  const counter_hash::Stream& s = a.stream;
  const auto scale = hn::Set(df, a.magnitude_scale);
  for (std::size_t i = 0; i < a.n; i += lanes) {
    // The key words of the three scatterers (shared by the looks) and their weights.
    hn::Vec<decltype(du)> key[kKept];
    VF w[kKept];
    const auto d0_or_nan = hn::Load(df, g.d0 + i);
    const auto valid = hn::Not(hn::IsNaN(d0_or_nan));
    const auto d0 = hn::IfThenElseZero(valid, d0_or_nan);
    const auto lo = hn::Load(du, g.lo + i);
    const auto hi = hn::Load(du, g.hi + i);
    for (int k = 0; k < kKept; ++k) {
      auto lo_k = lo, hi_k = hi;
      if (k > 0) {
        // Key of m_first + k: the low half plus k, the high half plus kHighMul where the low
        // half wrapped (lo + k < k unsigned: compared as signed with the top bits flipped).
        lo_k = hn::Add(lo, hn::Set(du, static_cast<std::uint32_t>(k)));
        const auto flipped = hn::BitCast(di, hn::Xor(lo_k, hn::Set(du, 0x80000000U)));
        const auto carry =
            hn::Lt(flipped, hn::Set(di, std::numeric_limits<std::int32_t>::min() + k));
        hi_k = hn::Add(
            hi, hn::BitCast(du, hn::IfThenElseZero(
                                    carry, hn::Set(di, static_cast<std::int32_t>(kHighMul)))));
      }
      key[k] = chv::key_word(du, s, lo_k, hi_k);
    }
    // w_k = exp(-1.125 (d0 + k)^2): w_1 = w_0 E, w_2 = w_1 E e^-2.25, E = exp(-2.25 d0 - 1.125).
    w[0] = hn::Exp(df, hn::Mul(hn::Set(df, -1.125f), hn::Mul(d0, d0)));
    const auto e = hn::Exp(df, hn::MulAdd(d0, hn::Set(df, -2.25f), hn::Set(df, -1.125f)));
    w[1] = hn::Mul(w[0], e);
    w[2] = hn::Mul(w[1], hn::Mul(e, hn::Set(df, 0.10539922456186433f)));
    // 1 / sum w^2: each sample's normalisation to unit mean power (the scatterers have unit
    // power).
    const auto w2 = hn::MulAdd(w[2], w[2], hn::MulAdd(w[1], w[1], hn::Mul(w[0], w[0])));
    hn::Store(hn::IfThenElse(valid, hn::Div(hn::Set(df, 1.0f), w2),
                             hn::Set(df, std::numeric_limits<float>::quiet_NaN())),
              df, g.inv_w2 + i);
    for (int j = 0; j < a.looks; ++j) {
      const std::uint32_t look = a.first_look + static_cast<std::uint32_t>(j);
      VF re = hn::Zero(df), im = hn::Zero(df);
      for (int k = 0; k < kKept; ++k) {
        VF zr, zi;
        Scatterer(df, du, chv::draw(du, s, key[k], look), scale, zr, zi);
        re = hn::MulAdd(w[k], zr, re);
        im = hn::MulAdd(w[k], zi, im);
      }
      hn::StoreU(re, df, a.re + static_cast<std::size_t>(j) * a.stride + i);
      hn::StoreU(im, df, a.im + static_cast<std::size_t>(j) * a.stride + i);
    }
  }
}

}  // namespace sonarsynth::lattice::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace sonarsynth::lattice {

HWY_EXPORT(GeometryBlock);
HWY_EXPORT(LatticeBlock);

std::size_t look_sums(const AlongTrackField& f, AlongTrackTable& table, std::size_t samples,
                      int first_look, int looks, std::vector<float>& re, std::vector<float>& im,
                      std::vector<double>& norm, const double* need) {
  simd::configure_from_environment();
  table.prepare(f.sample_spacing_m, f.beam_3db_rad, samples, f.array_length_m);
  const std::size_t stride = padded(samples);
  const auto nl = static_cast<std::size_t>(looks);
  re.resize(nl * stride);
  im.resize(nl * stride);
  norm.resize(stride);
  // 1 / sqrt(2 mean_neg_log_midpoints()): the 1 / sqrt(2) of the phase's rotation by pi/4
  // (Scatterer).
  static const auto magnitude_scale =
      static_cast<float>(1.0 / std::sqrt(2.0 * mean_neg_log_midpoints()));
  Geometry g;
  BlockArgs a{};
  a.g = &g;
  a.stream = line_stream(line_word(f));
  a.first_look = static_cast<std::uint32_t>(first_look);
  a.looks = looks;
  a.stride = stride;
  a.magnitude_scale = magnitude_scale;
  // Pings further apart than 2.5 footprints at every range (or no sample past the first
  // return): the lattice applies nowhere.
  const bool none = f.ping_spacing_m > 4.43 * table.sw_max || f.first_sample >= samples;
  GeometryArgs ga{};
  ga.g = &g;
  ga.along_track_m = f.along_track_m;
  ga.ping_spacing_m = f.ping_spacing_m;
  ga.first_sample = static_cast<double>(f.first_sample);
  // The last block's inputs, padded (where the lattice does not apply).
  std::vector<double>& pad = table.pad;
  std::size_t applied = 0;
  for (std::size_t i0 = 0; i0 < samples; i0 += kBlock) {
    const std::size_t count = std::min(kBlock, samples - i0);
    const std::size_t n = std::min(kBlock, (count + 15) / 16 * 16);
    ga.i0 = i0;
    ga.n = n;
    ga.inv_step = table.inv_step.data() + i0;
    ga.sw = table.sw.data() + i0;
    ga.need = need != nullptr ? need + i0 : nullptr;
    if (n > count && !none) {
      pad.assign(3 * n, std::numeric_limits<double>::quiet_NaN());
      std::copy_n(ga.inv_step, count, pad.begin());
      std::copy_n(ga.sw, count, pad.begin() + static_cast<std::ptrdiff_t>(n));
      ga.inv_step = pad.data();
      ga.sw = pad.data() + n;
      if (need != nullptr) {
        std::copy_n(ga.need, count, pad.begin() + static_cast<std::ptrdiff_t>(2 * n));
        ga.need = pad.data() + 2 * n;
      }
    }
    const std::size_t block_applied = none ? 0 : HWY_DYNAMIC_DISPATCH(GeometryBlock)(ga);
    applied += block_applied;
    if (block_applied == 0) {
      std::fill_n(norm.begin() + static_cast<std::ptrdiff_t>(i0), count,
                  std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    a.n = n;
    a.re = re.data() + i0;
    a.im = im.data() + i0;
    HWY_DYNAMIC_DISPATCH(LatticeBlock)(a);
    for (std::size_t t = 0; t < count; ++t) norm[i0 + t] = static_cast<double>(g.inv_w2[t]);
  }
  return applied;
}

}  // namespace sonarsynth::lattice
#endif  // HWY_ONCE
