// SPDX-License-Identifier: MIT
// The detector stage's vector kernel (sonarsynth/sensor_kernel.hpp): compiled once per target
// through hwy/foreach_target.h (AVX-512, AVX2 and the portable scalar target), chosen at run time.
#include "sonarsynth/sensor_kernel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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

void quantise(const QuantiseArgs& q, float* out, std::uint32_t& saturated, std::uint32_t& invalid) {
  simd::configure_from_environment();
  std::uint32_t counts[2] = {0, 0};
  HWY_DYNAMIC_DISPATCH(quantise_impl)(q, out, counts);
  saturated = counts[0];
  invalid = counts[1];
}

}  // namespace sonarsynth::sensor_kernel
#endif  // HWY_ONCE
