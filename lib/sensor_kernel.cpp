// SPDX-License-Identifier: MIT
// The detector stage's vector kernel (sonarsynth/sensor_kernel.hpp): compiled once per target
// through hwy/foreach_target.h (AVX-512, AVX2 and the portable scalar target), chosen at run time.
#include "sonarsynth/sensor_kernel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/simd.hpp"

// clang-format off
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "lib/sensor_kernel.cpp"
#include <hwy/foreach_target.h>
#include <hwy/highway.h>
#include "sonarsynth/counter_hash-inl.hpp"
// clang-format on

HWY_BEFORE_NAMESPACE();
namespace sonarsynth::sensor_kernel::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace ch = sonarsynth::counter_hash::HWY_NAMESPACE;

// Stream of the texture's Marsaglia–Tsang fallback beyond the tables (as in noise.cpp).
constexpr std::uint64_t kStreamTexture = 1u << 20;

// Samples per block: the block's float and word arrays (8 x 2 KiB) stay in L1 over the looks.
constexpr std::size_t kBlock = 512;

// -ln u of a word, u = uniform_open(w) in (0, 1) (a normal float, >= 2^-25): Exp(1), at most
// 17.3. u = 2^k m, m in [sqrt(1/2), sqrt(2)) (musl's reduction); ln m = x - x^2 / 2 + x^3 P(x),
// x = m - 1, P of degree 7 (least squares on Chebyshev nodes: |error| < 1e-8 on the interval,
// below float's rounding). No division, no table.
template <class DF, class DU>
HWY_INLINE hn::Vec<DF> exp1(DF df, DU du, hn::Vec<DU> w) {
  const hn::RebindToSigned<DU> di;
  const auto u = ch::uniform_open(df, du, w);
  const auto ix = hn::Add(hn::BitCast(du, u), hn::Set(du, 0x3f800000U - 0x3f3504f3U));
  const auto k = hn::Sub(hn::BitCast(di, hn::ShiftRight<23>(ix)), hn::Set(di, 127));
  const auto m =
      hn::BitCast(df, hn::Add(hn::And(ix, hn::Set(du, 0x7fffffU)), hn::Set(du, 0x3f3504f3U)));
  const auto x = hn::Sub(m, hn::Set(df, 1.0f));
  auto p = hn::Set(df, -0.0810311586f);
  p = hn::MulAdd(p, x, hn::Set(df, 0.127132242f));
  p = hn::MulAdd(p, x, hn::Set(df, -0.129720777f));
  p = hn::MulAdd(p, x, hn::Set(df, 0.142020356f));
  p = hn::MulAdd(p, x, hn::Set(df, -0.166422508f));
  p = hn::MulAdd(p, x, hn::Set(df, 0.200014747f));
  p = hn::MulAdd(p, x, hn::Set(df, -0.250002966f));
  p = hn::MulAdd(p, x, hn::Set(df, 0.333333285f));
  const auto x2 = hn::Mul(x, x);
  // ln m = x - x^2 / 2 + x^3 p; ln u = k ln 2 + ln m (ln 2 split in two for k up to 25).
  auto ln = hn::MulAdd(hn::Mul(x2, x), p, hn::NegMulAdd(x2, hn::Set(df, 0.5f), x));
  const auto kf = hn::ConvertTo(df, k);
  ln = hn::MulAdd(kf, hn::Set(df, 9.0580006145e-6f), ln);
  ln = hn::MulAdd(kf, hn::Set(df, 0.69313812256f), ln);
  return hn::Neg(ln);
}

// cos(theta), theta uniform on (-pi, pi), from a word: cos of a uniform angle on (0, pi / 2)
// (the high 24 bits) with the sign of the lowest bit, which has the same distribution. The
// Taylor series to theta^12 errs by < 7e-9 there (below float's rounding).
template <class DF, class DU>
HWY_INLINE hn::Vec<DF> cos_uniform(DF df, DU du, hn::Vec<DU> w) {
  const auto theta = hn::Mul(ch::uniform_open(df, du, w), hn::Set(df, 1.57079632679489661923f));
  const auto t = hn::Mul(theta, theta);
  auto c = hn::Set(df, 1.0f / 479001600.0f);
  c = hn::MulAdd(c, t, hn::Set(df, -1.0f / 3628800.0f));
  c = hn::MulAdd(c, t, hn::Set(df, 1.0f / 40320.0f));
  c = hn::MulAdd(c, t, hn::Set(df, -1.0f / 720.0f));
  c = hn::MulAdd(c, t, hn::Set(df, 1.0f / 24.0f));
  c = hn::MulAdd(c, t, hn::Set(df, -0.5f));
  c = hn::MulAdd(c, t, hn::Set(df, 1.0f));
  // The sign bit from the word's lowest bit.
  const auto sign = hn::BitCast(df, hn::ShiftLeft<31>(w));
  return hn::Xor(c, sign);
}

// sin(theta) on the same interval: the Taylor series to theta^13 errs by < 1e-9 there.
template <class DF>
HWY_INLINE hn::Vec<DF> sin_quarter(DF df, hn::Vec<DF> theta) {
  const auto t = hn::Mul(theta, theta);
  auto s = hn::Set(df, 1.0f / 6227020800.0f);
  s = hn::MulAdd(s, t, hn::Set(df, -1.0f / 39916800.0f));
  s = hn::MulAdd(s, t, hn::Set(df, 1.0f / 362880.0f));
  s = hn::MulAdd(s, t, hn::Set(df, -1.0f / 5040.0f));
  s = hn::MulAdd(s, t, hn::Set(df, 1.0f / 120.0f));
  s = hn::MulAdd(s, t, hn::Set(df, -1.0f / 6.0f));
  s = hn::MulAdd(s, t, hn::Set(df, 1.0f));
  return hn::Mul(s, theta);
}

// A unit phase e^(i phi), phi uniform on (-pi, pi], from a word: theta uniform on (0, pi / 2)
// from the high 24 bits, (cos theta, sin theta) reflected across the axes by bits 0 and 1 (the
// reflections of a uniform quarter turn cover the circle uniformly).
template <class DF, class DU>
HWY_INLINE void unit_phase(DF df, DU du, hn::Vec<DU> w, hn::Vec<DF>& c, hn::Vec<DF>& s) {
  const auto theta = hn::Mul(ch::uniform_open(df, du, w), hn::Set(df, 1.57079632679489661923f));
  const auto t = hn::Mul(theta, theta);
  auto cc = hn::Set(df, 1.0f / 479001600.0f);
  cc = hn::MulAdd(cc, t, hn::Set(df, -1.0f / 3628800.0f));
  cc = hn::MulAdd(cc, t, hn::Set(df, 1.0f / 40320.0f));
  cc = hn::MulAdd(cc, t, hn::Set(df, -1.0f / 720.0f));
  cc = hn::MulAdd(cc, t, hn::Set(df, 1.0f / 24.0f));
  cc = hn::MulAdd(cc, t, hn::Set(df, -0.5f));
  cc = hn::MulAdd(cc, t, hn::Set(df, 1.0f));
  const auto sign_c = hn::BitCast(df, hn::ShiftLeft<31>(w));
  const auto sign_s = hn::BitCast(df, hn::And(hn::ShiftLeft<30>(w), hn::Set(du, 0x80000000U)));
  c = hn::Xor(cc, sign_c);
  s = hn::Xor(sin_quarter(df, theta), sign_s);
}

// The key words of `count` keys into out[0 .. count rounded up to whole vectors) (the keys'
// 32-bit halves gathered from pairs of 64-bit vectors; the padding lanes hash key 0).
template <class DU>
void key_words(DU du, const std::uint64_t* keys, std::size_t count, const counter_hash::Stream& st,
               std::uint32_t* out) {
  [[maybe_unused]] const hn::Repartition<std::uint64_t, DU> du64;
  const std::size_t L = hn::Lanes(du);
#if HWY_TARGET == HWY_SCALAR
  const std::size_t wlen = 0;
#else
  const std::size_t Ld = hn::Lanes(du64);
  const std::size_t wlen = count / L * L;
  for (std::size_t i = 0; i < wlen; i += L) {
    const auto k0 = hn::BitCast(du, hn::LoadU(du64, keys + i));
    const auto k1 = hn::BitCast(du, hn::LoadU(du64, keys + i + Ld));
    hn::StoreU(ch::key_word(du, st, hn::ConcatEven(du, k1, k0), hn::ConcatOdd(du, k1, k0)), du,
               out + i);
  }
#endif
  HWY_ALIGN std::uint32_t lo[hn::MaxLanes(du)], hi[hn::MaxLanes(du)];
  for (std::size_t i = wlen; i < count; i += L) {
    for (std::size_t l = 0; l < L; ++l) {
      const std::uint64_t k = i + l < count ? keys[i + l] : 0;
      lo[l] = static_cast<std::uint32_t>(k);
      hi[l] = static_cast<std::uint32_t>(k >> 32);
    }
    hn::StoreU(ch::key_word(du, st, hn::Load(du, lo), hn::Load(du, hi)), du, out + i);
  }
}

void detect_impl(const DetectorArgs& a, counter_hash::Stream ss, counter_hash::Stream sn) {
  const hn::ScalableTag<float> df;
  const hn::RebindToUnsigned<decltype(df)> du;
  const std::size_t L = hn::Lanes(df);
  HWY_ALIGN float bg[kBlock], mg[kBlock], acc[kBlock], fld[kBlock];
  HWY_ALIGN std::uint32_t hs[kBlock], hnw[kBlock];
  HWY_ALIGN std::uint32_t lo[kBlock], hi[kBlock];
  const hn::Repartition<double, decltype(df)> dd;  // half as many lanes
  const hn::Rebind<float, decltype(dd)> dfh;
  [[maybe_unused]] const hn::Repartition<std::uint64_t, decltype(du)> du64;
  const std::size_t Ld = hn::Lanes(dd);
  const bool thermal = a.thermal_power > 0.0, floor = a.floor_power > 0.0;
  const auto zero = hn::Zero(df);
  const auto two = hn::Set(df, 2.0f);
  for (std::size_t b0 = 0; b0 < a.n; b0 += kBlock) {
    const std::size_t len = std::min(kBlock, a.n - b0);
    // Padded to whole vectors: the tail lanes compute on zeros and are not stored.
    const std::size_t padded = (len + L - 1) / L * L;
    // The block in float32 scaled by a power of two (exact, the same on every target) that
    // puts its largest finite power near 1: output powers span more than float's range
    // (amplitude output up to float's maximum is a power of 1e77).
    const double* base = a.base + b0;
    const double* gain = a.gain + b0;
    const std::size_t vlen = len / Ld * Ld;
    auto top_v = hn::Zero(dd);
    const auto th = hn::Set(dd, a.thermal_power);
    for (std::size_t i = 0; i < vlen; i += Ld) {
      const auto g = hn::LoadU(dd, gain + i);
      const auto vb = hn::Mul(hn::LoadU(dd, base + i), g), vt = hn::Mul(th, g);
      top_v = hn::Max(top_v, hn::IfThenElseZero(hn::IsFinite(vb), vb));
      top_v = hn::Max(top_v, hn::IfThenElseZero(hn::IsFinite(vt), vt));
    }
    double top = std::max(a.floor_power, hn::GetLane(hn::MaxOfLanes(dd, top_v)));
    for (std::size_t i = vlen; i < len; ++i) {
      for (const double v : {base[i] * gain[i], a.thermal_power * gain[i]}) {
        if (std::isfinite(v)) top = std::max(top, v);
      }
    }
    // An even exponent: the square roots of the mean detector scale exactly too, so that a
    // sample's output does not depend on the other samples of its block.
    const int e = top > 0.0 ? std::ilogb(top) & ~1 : 0;
    const double scale = std::ldexp(1.0, -e), unscale = std::ldexp(1.0, e);
    const auto scale_v = hn::Set(dd, scale);
    auto any_v = hn::Zero(dd);  // max of base gain where not NaN: > 0 if any mean > 0
    for (std::size_t i = 0; i < vlen; i += Ld) {
      const auto g = hn::Mul(hn::LoadU(dd, gain + i), scale_v);
      const auto vb = hn::Mul(hn::LoadU(dd, base + i), g);
      any_v = hn::Max(any_v, hn::IfThenZeroElse(hn::IsNaN(vb), vb));
      hn::StoreU(hn::DemoteTo(dfh, vb), dfh, bg + i);
      hn::StoreU(hn::DemoteTo(dfh, hn::Mul(th, g)), dfh, mg + i);
    }
    bool any_mean = hn::GetLane(hn::MaxOfLanes(dd, any_v)) > 0.0;
    for (std::size_t i = vlen; i < padded; ++i) {
      const bool in = i < len;
      const double g = in ? gain[i] * scale : 0.0;
      bg[i] = in ? static_cast<float>(base[i] * g) : 0.0f;
      mg[i] = static_cast<float>(a.thermal_power * g);
      any_mean |= bg[i] > 0.0f;
    }
    const auto floor_v = hn::Set(df, static_cast<float>(a.floor_power * scale));
    // The key words of a block: the keys' 32-bit halves gathered from pairs of 64-bit vectors.
    const auto key_words = [&](const std::uint64_t* keys, const counter_hash::Stream& st,
                               std::uint32_t* out) {
#if HWY_TARGET == HWY_SCALAR
      const std::size_t wlen = 0;
#else
      const std::size_t wlen = len / L * L;
      for (std::size_t i = 0; i < wlen; i += L) {
        const auto k0 = hn::BitCast(du, hn::LoadU(du64, keys + i));
        const auto k1 = hn::BitCast(du, hn::LoadU(du64, keys + i + Ld));
        hn::Store(ch::key_word(du, st, hn::ConcatEven(du, k1, k0), hn::ConcatOdd(du, k1, k0)), du,
                  out + i);
      }
#endif
      if (wlen < padded) {
        for (std::size_t i = wlen; i < padded; ++i) {
          const std::uint64_t k = i < len ? keys[i] : 0;
          lo[i - wlen] = static_cast<std::uint32_t>(k);
          hi[i - wlen] = static_cast<std::uint32_t>(k >> 32);
        }
        for (std::size_t i = wlen; i < padded; i += L) {
          hn::Store(
              ch::key_word(du, st, hn::Load(du, lo + (i - wlen)), hn::Load(du, hi + (i - wlen))),
              du, out + i);
        }
      }
    };
    // Speckle key words only where a speckle draw may be needed (some mean > 0).
    if (any_mean) key_words(a.keys + b0, ss, hs);
    if (thermal || floor) key_words(a.noise_keys + b0, sn, hnw);
    for (int j = 0; j < a.looks; ++j) {
      const auto ju = static_cast<std::uint32_t>(j);
      const bool have_field = a.field != nullptr;
      if (have_field && any_mean) {
        const double* f = a.field + static_cast<std::size_t>(j) * a.n + b0;
        for (std::size_t i = 0; i < padded; ++i) fld[i] = i < len ? static_cast<float>(f[i]) : 0.0f;
      }
      for (std::size_t i = 0; i < padded; i += L) {
        const auto m = hn::Load(df, bg + i);
        // Where the mean is not > 0 (shadow: 0; bad input: negative or NaN, kept so that the
        // quantiser counts it) there is no speckle to draw.
        auto p = m;
        const auto has_mean = hn::Gt(m, zero);
        if (!hn::AllFalse(df, has_mean)) {
          // The frozen speckle: the lattice's power where it applies, else drawn per key.
          if (have_field) {
            const auto f = hn::Load(df, fld + i);
            const auto draw_here = hn::And(hn::IsNaN(f), has_mean);
            auto es = f;
            if (!hn::AllFalse(df, draw_here)) {
              es = hn::IfThenElse(draw_here,
                                  exp1(df, du, ch::draw(du, ss, hn::Load(du, hs + i), ju)), f);
            }
            p = hn::IfThenElse(has_mean, hn::Mul(m, es), m);
          } else {
            p = hn::IfThenElse(
                has_mean, hn::Mul(m, exp1(df, du, ch::draw(du, ss, hn::Load(du, hs + i), ju))), m);
          }
        }
        if (thermal) {
          // |s + n|^2 with the phase of n relative to s uniform: A + M E + 2 sqrt(A M E) cos.
          const auto h = hn::Load(du, hnw + i);
          const auto me = hn::Mul(hn::Load(df, mg + i),
                                  exp1(df, du, ch::draw(du, sn, h, ju * kNoiseWordsPerLook)));
          const auto c = cos_uniform(df, du, ch::draw(du, sn, h, ju * kNoiseWordsPerLook + 1));
          const auto cross = hn::Mul(two, hn::Sqrt(hn::Mul(p, me)));
          p = hn::MulAdd(cross, c, hn::Add(p, me));
          p = hn::IfThenElse(hn::Lt(p, zero), zero, p);  // rounding only: exactly >= 0
        }
        if (floor) {
          const auto h = hn::Load(du, hnw + i);
          p = hn::MulAdd(floor_v, exp1(df, du, ch::draw(du, sn, h, ju * kNoiseWordsPerLook + 2)),
                         p);
        }
        if (j == 0) {
          hn::Store(a.max_detector ? p : hn::Sqrt(p), df, acc + i);
        } else if (a.max_detector) {
          hn::Store(hn::Max(hn::Load(df, acc + i), p), df, acc + i);
        } else {
          hn::Store(hn::Add(hn::Load(df, acc + i), hn::Sqrt(p)), df, acc + i);
        }
      }
    }
    double* out = a.out + b0;
    const auto unscale_v = hn::Set(dd, unscale);
    const double inv = 1.0 / static_cast<double>(a.looks);
    const auto inv_v = hn::Set(dd, inv);
    for (std::size_t i = 0; i < vlen; i += Ld) {
      auto v = hn::PromoteTo(dd, hn::LoadU(dfh, acc + i));
      if (!a.max_detector) {
        v = hn::Mul(v, inv_v);
        v = hn::Mul(v, v);
      }
      hn::StoreU(hn::Mul(v, unscale_v), dd, out + i);
    }
    for (std::size_t i = vlen; i < len; ++i) {
      double v = static_cast<double>(acc[i]);
      if (!a.max_detector) {
        v *= inv;
        v *= v;
      }
      out[i] = v * unscale;
    }
  }
}

// The texture (TextureArgs): the words per block in 32-bit lanes, the table's bins gathered in
// double lanes; the two exactly inverted tail bins and shapes beyond the tables per lane in
// scalar code.
void texture_impl(const TextureArgs& a, counter_hash::Stream ss) {
  const hn::ScalableTag<std::uint32_t> du;
  const hn::ScalableTag<double> dd;
  const hn::RebindToUnsigned<decltype(dd)> du64;
  const hn::Rebind<std::uint32_t, decltype(dd)> duh;
  const hn::Rebind<std::int32_t, decltype(dd)> dih;
  const hn::Rebind<float, decltype(dd)> dfh;
  const std::size_t Ld = hn::Lanes(dd);
  HWY_ALIGN std::uint32_t w[kBlock + 64];
  constexpr std::uint64_t kLast = UnitGammaTable::kBins - 1;
  const UnitGammaTable* table = nullptr;
  double table_nu = 0.0;
  const auto table_of = [&](double nu) -> const UnitGammaTable& {
    if (table == nullptr || nu != table_nu) {
      table = &UnitGammaTable::get(nu);
      table_nu = nu;
    }
    return *table;
  };
  // The scalar rule of one sample (the tail bins and shapes beyond the tables).
  const auto scalar_texture = [&](std::size_t i, std::uint32_t word) {
    const double nu = a.nu[i];
    if (nu <= UnitGammaTable::kMaxShape) {
      return table_of(nu)(high32_midpoint(static_cast<std::uint64_t>(word) << 32));
    }
    return keyed_gamma(nu, a.seed, a.keys[i], kStreamTexture) / nu;
  };
  const auto zero = hn::Zero(dd);
  const auto max_shape = hn::Set(dd, UnitGammaTable::kMaxShape);
  for (std::size_t b0 = 0; b0 < a.n; b0 += kBlock) {
    const std::size_t len = std::min(kBlock, a.n - b0);
    const double* mean = a.mean + b0;
    const double* nu = a.nu + b0;
    double* base = a.base + b0;
    key_words(du, a.keys + b0, len, ss, w);
    for (std::size_t i = 0; i < len; i += hn::Lanes(du)) {
      hn::Store(ch::draw(du, ss, hn::Load(du, w + i), kTextureCounter), du, w + i);
    }
    const std::size_t vlen = len / Ld * Ld;
    for (std::size_t i = 0; i < vlen; i += Ld) {
      const auto m = hn::LoadU(dd, mean + i);
      const auto v_nu = hn::LoadU(dd, nu + i);
      const auto textured = hn::And(hn::Gt(m, zero), hn::Gt(v_nu, zero));
      if (hn::AllFalse(dd, textured)) {
        hn::StoreU(m, dd, base + i);
        continue;
      }
      const auto tabled = hn::And(textured, hn::Le(v_nu, max_shape));
      const auto w32 = hn::LoadU(duh, w + i);
      const auto k = hn::ShiftRight<20>(w32);
      const auto k64 = hn::ShiftRight<20>(hn::PromoteTo(du64, w32));
      const auto tail = hn::Or(hn::Eq(k64, hn::Zero(du64)), hn::Eq(k64, hn::Set(du64, kLast)));
      const auto special =
          hn::Or(hn::AndNot(tabled, textured), hn::And(tabled, hn::RebindMask(dd, tail)));
      // frac = (m + 1/2) 2^-20, m the word's low 20 bits (exact in float).
      const auto frac =
          hn::MulAdd(hn::ConvertTo(dfh, hn::BitCast(dih, hn::And(w32, hn::Set(duh, 0xfffffU)))),
                     hn::Set(dfh, 0x1p-20f), hn::Set(dfh, 0x1p-21f));
      const auto idx = hn::BitCast(dih, k);
      auto t = hn::Set(dd, 1.0);
      auto left = tabled;
      while (!hn::AllFalse(dd, left)) {
        HWY_ALIGN double lanes_nu[hn::MaxLanes(dd)];
        hn::Store(v_nu, dd, lanes_nu);
        const double nu0 = lanes_nu[static_cast<std::size_t>(hn::FindFirstTrue(dd, left))];
        const auto here = hn::And(left, hn::Eq(v_nu, hn::Set(dd, nu0)));
        const float* bins = table_of(nu0).bins_float();
        const auto x = hn::GatherIndex(dfh, bins, idx);
        const auto d = hn::GatherIndex(dfh, bins + UnitGammaTable::kBins, idx);
        const auto c = hn::GatherIndex(dfh, bins + 2 * UnitGammaTable::kBins, idx);
        // x + frac (d + c (1 - frac)), UnitGammaTable::operator()'s quadratic in float32.
        const auto v = hn::MulAdd(frac, hn::MulAdd(c, hn::Sub(hn::Set(dfh, 1.0f), frac), d), x);
        t = hn::IfThenElse(here, hn::PromoteTo(dd, v), t);
        left = hn::AndNot(here, left);
      }
      hn::StoreU(hn::IfThenElse(textured, hn::Mul(m, t), m), dd, base + i);
      if (!hn::AllFalse(dd, special)) {
        for (std::size_t l = 0; l < Ld; ++l) {
          const std::size_t j = i + l;
          if (!(mean[j] > 0.0) || !(nu[j] > 0.0)) continue;
          const std::uint64_t kj = w[j] >> 20;
          if (nu[j] <= UnitGammaTable::kMaxShape && kj != 0 && kj != kLast) continue;
          base[j] = mean[j] * scalar_texture(b0 + j, w[j]);
        }
      }
    }
    for (std::size_t j = vlen; j < len; ++j) {
      base[j] = mean[j] > 0.0 && nu[j] > 0.0 ? mean[j] * scalar_texture(b0 + j, w[j]) : mean[j];
    }
  }
}

// The range-filtered detector (FilteredArgs): per block, the complex echo of the block and a halo
// of K samples each side in float32 (amplitudes scaled by a power of two from the largest mean
// power of the block and halo), the taps as a vector FIR over the block, the detector as
// detect_impl's (output powers scaled by a second power of two).
void filtered_impl(const FilteredArgs& a, counter_hash::Stream ss, counter_hash::Stream sn) {
  const hn::ScalableTag<float> df;
  const hn::RebindToUnsigned<decltype(df)> du;
  const std::size_t L = hn::Lanes(df);
  const hn::Repartition<double, decltype(df)> dd;
  const hn::Rebind<float, decltype(dd)> dfh;
  const std::size_t Ld = hn::Lanes(dd);
  constexpr std::size_t kExt = kBlock + 2 * kMaxHalfTaps + 64;
  HWY_ALIGN float amp[kExt], amp_field[kExt], amp_thermal[kExt], zr[kExt], zi[kExt];
  HWY_ALIGN float fre[kExt], fim[kExt], gain[kBlock], acc[kBlock];
  HWY_ALIGN std::uint32_t hs[kExt], hnw[kExt];
  const std::size_t K = a.taps_n / 2;
  float taps[2 * kMaxHalfTaps + 1];
  for (std::size_t k = 0; k < a.taps_n; ++k) taps[k] = static_cast<float>(a.taps[k]);
  const bool thermal = a.thermal_power > 0.0, floor = a.floor_power > 0.0;
  const bool lattice = a.field_norm != nullptr;
  const auto zero = hn::Zero(df);
  const auto n = static_cast<std::ptrdiff_t>(a.n);
  for (std::size_t b0 = 0; b0 < a.n; b0 += kBlock) {
    const std::size_t len = std::min(kBlock, a.n - b0);
    const std::size_t padded = (len + L - 1) / L * L;
    const std::size_t ext = (padded + 2 * K + L - 1) / L * L;
    // Ext index u is sample t = b0 - K + u; [u0, u1) the samples inside the record.
    const std::ptrdiff_t t0 = static_cast<std::ptrdiff_t>(b0) - static_cast<std::ptrdiff_t>(K);
    const auto u0 = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, -t0));
    const auto u1 = static_cast<std::size_t>(
        std::min<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(ext), n - t0));
    const double* base = a.base + (t0 + static_cast<std::ptrdiff_t>(u0));
    const double* gn = a.gain + (t0 + static_cast<std::ptrdiff_t>(u0));
    const double* norm = lattice ? a.field_norm + (t0 + static_cast<std::ptrdiff_t>(u0)) : nullptr;
    const std::size_t cnt = u1 - u0;
    // The two scales: amplitudes from the largest mean power (and N) of block and halo, output
    // powers from the largest of mean and noise powers times the gain, and the floor.
    const std::size_t vcnt = cnt / Ld * Ld;
    double top_a = a.thermal_power, top_o = a.floor_power;
    {
      auto ta = hn::Zero(dd), to = hn::Zero(dd);
      const auto th = hn::Set(dd, a.thermal_power);
      for (std::size_t u = 0; u < vcnt; u += Ld) {
        const auto b = hn::LoadU(dd, base + u), g = hn::LoadU(dd, gn + u);
        const auto vb = hn::Mul(b, g), vt = hn::Mul(th, g);
        ta = hn::Max(ta, hn::IfThenElseZero(hn::IsFinite(b), b));
        to = hn::Max(to, hn::IfThenElseZero(hn::IsFinite(vb), vb));
        to = hn::Max(to, hn::IfThenElseZero(hn::IsFinite(vt), vt));
      }
      top_a = std::max(top_a, hn::GetLane(hn::MaxOfLanes(dd, ta)));
      top_o = std::max(top_o, hn::GetLane(hn::MaxOfLanes(dd, to)));
    }
    for (std::size_t u = vcnt; u < cnt; ++u) {
      const double b = base[u];
      if (b > 0.0 && std::isfinite(b)) top_a = std::max(top_a, b);
      for (const double v : {b * gn[u], a.thermal_power * gn[u]}) {
        if (std::isfinite(v)) top_o = std::max(top_o, v);
      }
    }
    const int ea = top_a > 0.0 ? std::ilogb(top_a) & ~1 : 0;
    const int eo = top_o > 0.0 ? std::ilogb(top_o) & ~1 : 0;
    const double sa2 = std::ldexp(1.0, -ea);
    const auto sa2_v = hn::Set(dd, sa2);
    const auto zero_d = hn::Zero(dd);
    std::fill(amp, amp + ext, 0.0f);
    std::fill(amp_field, amp_field + ext, 0.0f);
    std::fill(amp_thermal, amp_thermal + ext, 0.0f);
    std::fill(amp_thermal + u0, amp_thermal + u1,
              static_cast<float>(std::sqrt(a.thermal_power * sa2)));
    bool any_mean = false;
    auto any_v = hn::Zero(dd);
    for (std::size_t u = 0; u < vcnt; u += Ld) {
      const auto b = hn::LoadU(dd, base + u);
      const auto has = hn::Gt(b, zero_d);
      const auto bs = hn::IfThenElseZero(has, hn::Mul(b, sa2_v));
      any_v = hn::Max(any_v, bs);
      hn::StoreU(hn::DemoteTo(dfh, hn::Sqrt(bs)), dfh, amp + u0 + u);
      if (lattice) {
        const auto fa = hn::IfThenElseZero(has, hn::Sqrt(hn::Mul(hn::LoadU(dd, norm + u), bs)));
        hn::StoreU(hn::DemoteTo(dfh, fa), dfh, amp_field + u0 + u);
      }
    }
    any_mean = hn::GetLane(hn::MaxOfLanes(dd, any_v)) > 0.0;
    for (std::size_t u = vcnt; u < cnt; ++u) {
      const double b = base[u];
      if (!(b > 0.0)) continue;
      any_mean = true;
      amp[u0 + u] = static_cast<float>(std::sqrt(b * sa2));
      if (lattice) amp_field[u0 + u] = static_cast<float>(std::sqrt(norm[u] * (b * sa2)));
    }
    // gain_i 2^(ea - eo) / w2_i, w2_i the power of the taps inside the record.
    const double g_scale = std::ldexp(1.0, ea - eo);
    const std::size_t vlen_g = len / Ld * Ld;
    for (std::size_t i = 0; i < vlen_g; i += Ld) {
      const auto g = hn::Mul(hn::LoadU(dd, a.gain + b0 + i), hn::Set(dd, g_scale));
      hn::StoreU(hn::DemoteTo(dfh, g), dfh, gain + i);
    }
    for (std::size_t i = vlen_g; i < padded; ++i) {
      gain[i] = i < len ? static_cast<float>(a.gain[b0 + i] * g_scale) : 0.0f;
    }
    // Near the record's ends: divided by the power of the taps inside it.
    for (std::size_t i = 0; i < len; ++i) {
      const std::size_t t = b0 + i;
      if (t >= K && t + K < a.n) {
        if (t + K + kBlock < a.n) break;  // no end in this block
        continue;
      }
      double w2 = 0.0;
      for (std::size_t k = 0; k < a.taps_n; ++k) {
        const std::size_t u = t + k;  // sample u - K
        if (u >= K && u - K < a.n) w2 += a.taps[k] * a.taps[k];
      }
      gain[i] = static_cast<float>(a.gain[t] * g_scale / w2);
    }
    std::fill(hs, hs + ext + L, 0u);
    std::fill(hnw, hnw + ext + L, 0u);
    if (any_mean) key_words(du, a.keys + (t0 + static_cast<std::ptrdiff_t>(u0)), cnt, ss, hs + u0);
    if (thermal || floor) {
      key_words(du, a.noise_keys + (t0 + static_cast<std::ptrdiff_t>(u0)), cnt, sn, hnw + u0);
    }
    const auto floor_v = hn::Set(df, static_cast<float>(a.floor_power * std::ldexp(1.0, -eo)));
    for (int j = 0; j < a.looks; ++j) {
      const auto ju = static_cast<std::uint32_t>(j);
      if (lattice && any_mean) {
        const float* re = a.field_re + static_cast<std::size_t>(j) * a.field_stride;
        const float* im = a.field_im + static_cast<std::size_t>(j) * a.field_stride;
        std::fill(fre, fre + ext, 0.0f);
        std::fill(fim, fim + ext, 0.0f);
        std::copy(re + (t0 + static_cast<std::ptrdiff_t>(u0)),
                  re + (t0 + static_cast<std::ptrdiff_t>(u1)), fre + u0);
        std::copy(im + (t0 + static_cast<std::ptrdiff_t>(u0)),
                  im + (t0 + static_cast<std::ptrdiff_t>(u1)), fim + u0);
      }
      for (std::size_t u = 0; u < ext; u += L) {
        auto r = zero, i = zero;
        const auto am = hn::Load(df, amp + u);
        const auto has = hn::Gt(am, zero);
        if (!hn::AllFalse(df, has)) {
          auto draw_here = has;
          if (lattice) {
            const auto af = hn::Load(df, amp_field + u);
            const auto fr = hn::Mul(hn::Load(df, fre + u), af);
            const auto fi = hn::Mul(hn::Load(df, fim + u), af);
            const auto use = hn::And(has, hn::Not(hn::IsNaN(fr)));
            r = hn::IfThenElseZero(use, fr);
            i = hn::IfThenElseZero(use, fi);
            draw_here = hn::AndNot(use, has);
          }
          if (!hn::AllFalse(df, draw_here)) {
            const auto h = hn::Load(du, hs + u);
            const auto ra = hn::Mul(hn::Sqrt(exp1(df, du, ch::draw(du, ss, h, ju))), am);
            hn::Vec<decltype(df)> c, s;
            unit_phase(df, du, ch::draw(du, ss, h, kPhaseCounter + ju), c, s);
            r = hn::IfThenElse(draw_here, hn::Mul(ra, c), r);
            i = hn::IfThenElse(draw_here, hn::Mul(ra, s), i);
          }
        }
        if (thermal) {
          const auto h = hn::Load(du, hnw + u);
          const auto ra =
              hn::Mul(hn::Sqrt(exp1(df, du, ch::draw(du, sn, h, ju * kNoiseWordsPerLook))),
                      hn::Load(df, amp_thermal + u));
          hn::Vec<decltype(df)> c, s;
          unit_phase(df, du, ch::draw(du, sn, h, ju * kNoiseWordsPerLook + 1), c, s);
          r = hn::MulAdd(ra, c, r);
          i = hn::MulAdd(ra, s, i);
        }
        hn::Store(r, df, zr + u);
        hn::Store(i, df, zi + u);
      }
      for (std::size_t o = 0; o < padded; o += L) {
        auto yr = zero, yi = zero;
        for (std::size_t k = 0; k < a.taps_n; ++k) {
          const auto h = hn::Set(df, taps[k]);
          yr = hn::MulAdd(h, hn::LoadU(df, zr + o + k), yr);
          yi = hn::MulAdd(h, hn::LoadU(df, zi + o + k), yi);
        }
        auto p = hn::Mul(hn::MulAdd(yr, yr, hn::Mul(yi, yi)), hn::Load(df, gain + o));
        if (floor) {
          const auto h = hn::LoadU(du, hnw + o + K);
          p = hn::MulAdd(floor_v, exp1(df, du, ch::draw(du, sn, h, ju * kNoiseWordsPerLook + 2)),
                         p);
        }
        if (j == 0) {
          hn::Store(a.max_detector ? p : hn::Sqrt(p), df, acc + o);
        } else if (a.max_detector) {
          hn::Store(hn::Max(hn::Load(df, acc + o), p), df, acc + o);
        } else {
          hn::Store(hn::Add(hn::Load(df, acc + o), hn::Sqrt(p)), df, acc + o);
        }
      }
    }
    double* out = a.out + b0;
    const double unscale = std::ldexp(1.0, eo);
    const double inv = 1.0 / static_cast<double>(a.looks);
    const std::size_t vlen = len / Ld * Ld;
    for (std::size_t o = 0; o < vlen; o += Ld) {
      auto v = hn::PromoteTo(dd, hn::LoadU(dfh, acc + o));
      if (!a.max_detector) {
        v = hn::Mul(v, hn::Set(dd, inv));
        v = hn::Mul(v, v);
      }
      hn::StoreU(hn::Mul(v, hn::Set(dd, unscale)), dd, out + o);
    }
    for (std::size_t o = vlen; o < len; ++o) {
      double v = static_cast<double>(acc[o]);
      if (!a.max_detector) {
        v *= inv;
        v *= v;
      }
      out[o] = v * unscale;
    }
  }
}

// The quantiser (QuantiseArgs), in double: the same operations as its scalar form in the
// same order, so every target gives the same bits.
void quantise_impl(const QuantiseArgs& q, float* out, std::uint32_t* counts) {
  const hn::ScalableTag<double> dd;
  const hn::Rebind<float, decltype(dd)> dfh;
  const std::size_t Ld = hn::Lanes(dd);
  std::uint32_t saturated = 0, invalid = 0;
  const auto maxv = hn::Set(dd, q.max_value);
  const auto zero = hn::Zero(dd);
  const auto half = hn::Set(dd, 0.5);
  const auto one = hn::Set(dd, 1.0);
  const auto big = hn::Set(dd, 0x1p52);
  std::size_t i = q.first;
  for (; i + Ld <= q.n; i += Ld) {
    auto v = hn::LoadU(dd, q.power + i);
    if (q.gain != nullptr) v = hn::Mul(v, hn::LoadU(dd, q.gain + i));
    if (q.amplitude) v = hn::Sqrt(v);
    const auto bad = hn::Not(hn::IsFinite(v));
    const auto sat = hn::AndNot(bad, hn::Ge(v, maxv));
    invalid += static_cast<std::uint32_t>(hn::CountTrue(dd, bad));
    saturated += static_cast<std::uint32_t>(hn::CountTrue(dd, sat));
    v = hn::IfThenElse(sat, maxv, v);
    v = hn::IfThenZeroElse(hn::Or(bad, hn::Lt(v, zero)), v);
    if (q.round) {
      // round half away from zero of v in [0, 2^52): trunc(v) + (v - trunc(v) >= 1/2), exact.
      const auto t = hn::Trunc(v);
      const auto r = hn::Add(t, hn::IfThenElseZero(hn::Ge(hn::Sub(v, t), half), one));
      v = hn::IfThenElse(hn::Lt(v, big), r, v);
    }
    hn::StoreU(hn::DemoteTo(dfh, v), dfh, out + i);
  }
  for (; i < q.n; ++i) {
    double v = q.power[i];
    if (q.gain != nullptr) v *= q.gain[i];
    if (q.amplitude) v = std::sqrt(v);
    if (!std::isfinite(v)) {
      v = 0.0;
      ++invalid;
    } else if (v >= q.max_value) {
      v = q.max_value;
      ++saturated;
    } else if (v < 0.0) {
      v = 0.0;
    }
    if (q.round && v < 0x1p52) {
      const double t = std::trunc(v);
      v = t + static_cast<double>(v - t >= 0.5);
    }
    out[i] = static_cast<float>(v);
  }
  counts[0] = saturated;
  counts[1] = invalid;
}

}  // namespace sonarsynth::sensor_kernel::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace sonarsynth::sensor_kernel {

HWY_EXPORT(detect_impl);
HWY_EXPORT(quantise_impl);
HWY_EXPORT(texture_impl);
HWY_EXPORT(filtered_impl);

namespace {
// Salts of the two streams (distinct from every other keyed stream of the run seed).
constexpr std::uint64_t kSpeckleSalt = 0x5be1c1e0f7a2d3b5ULL;
constexpr std::uint64_t kNoiseSalt = 0x7e4a1b0c9d2f3e61ULL;
}  // namespace

counter_hash::Stream speckle_stream(std::uint64_t seed) {
  return counter_hash::Stream::of(splitmix64(seed ^ kSpeckleSalt));
}
counter_hash::Stream noise_stream(std::uint64_t seed) {
  return counter_hash::Stream::of(splitmix64(seed ^ kNoiseSalt));
}

void detect(const DetectorArgs& a) {
  simd::configure_from_environment();
  HWY_DYNAMIC_DISPATCH(detect_impl)(a, speckle_stream(a.seed), noise_stream(a.seed));
}

void texture(const TextureArgs& a) {
  if (a.nu == nullptr) {
    std::copy(a.mean, a.mean + a.n, a.base);
    return;
  }
  simd::configure_from_environment();
  HWY_DYNAMIC_DISPATCH(texture_impl)(a, speckle_stream(a.seed));
}

void detect_filtered(const FilteredArgs& a) {
  if (a.taps_n == 0 || a.taps_n % 2 == 0 || a.taps_n / 2 > kMaxHalfTaps) {
    throw std::invalid_argument(
        "sensor_kernel::detect_filtered: taps_n = " + std::to_string(a.taps_n) +
        ". Violated constraint: odd, 1 <= taps_n <= " + std::to_string(2 * kMaxHalfTaps + 1));
  }
  simd::configure_from_environment();
  HWY_DYNAMIC_DISPATCH(filtered_impl)(a, speckle_stream(a.seed), noise_stream(a.seed));
}

void quantise(const QuantiseArgs& q, float* out, std::uint32_t& saturated, std::uint32_t& invalid) {
  simd::configure_from_environment();
  std::uint32_t counts[2] = {0, 0};
  HWY_DYNAMIC_DISPATCH(quantise_impl)(q, out, counts);
  saturated = counts[0];
  invalid = counts[1];
}

}  // namespace sonarsynth::sensor_kernel
#endif  // HWY_ONCE
