// SPDX-License-Identifier: MIT
// The building blocks of the detector's vector kernels (lib/sensor_kernel.cpp) on Highway
// vectors: the random draws (Exp(1) powers, uniform phases), the key words of a block, the look
// accumulator and the detected output (per target: include after hwy/highway.h in a file compiled
// through hwy/foreach_target.h).
#if defined(SONARSYNTH_SENSOR_KERNEL_BLOCKS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SONARSYNTH_SENSOR_KERNEL_BLOCKS_INL_H_
#undef SONARSYNTH_SENSOR_KERNEL_BLOCKS_INL_H_
#else
#define SONARSYNTH_SENSOR_KERNEL_BLOCKS_INL_H_
#endif

#include <hwy/highway.h>

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "sonarsynth/counter_hash-inl.hpp"
#include "sonarsynth/counter_hash.hpp"

HWY_BEFORE_NAMESPACE();
namespace sonarsynth::sensor_kernel::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace ch = sonarsynth::counter_hash::HWY_NAMESPACE;

// c_0 t^n + c_1 t^(n-1) + ... + c_n by Horner's rule, one MulAdd per coefficient (coefficients
// highest degree first, as numpy.polyval takes them).
template <class DF, class... C>
HWY_INLINE hn::Vec<DF> polyval(DF df, hn::Vec<DF> t, float c0, C... c) {
  auto p = hn::Set(df, c0);
  ((p = hn::MulAdd(p, t, hn::Set(df, c))), ...);
  return p;
}

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
  const auto p = polyval(df, x, -0.0810311586f, 0.127132242f, -0.129720777f, 0.142020356f,
                         -0.166422508f, 0.200014747f, -0.250002966f, 0.333333285f);
  const auto x2 = hn::Mul(x, x);
  // ln m = x - x^2 / 2 + x^3 p; ln u = k ln 2 + ln m (ln 2 split in two for k up to 25).
  auto ln = hn::MulAdd(hn::Mul(x2, x), p, hn::NegMulAdd(x2, hn::Set(df, 0.5f), x));
  const auto kf = hn::ConvertTo(df, k);
  ln = hn::MulAdd(kf, hn::Set(df, 9.0580006145e-6f), ln);
  ln = hn::MulAdd(kf, hn::Set(df, 0.69313812256f), ln);
  return hn::Neg(ln);
}

// theta uniform on (0, pi / 2) from a word's high 24 bits.
template <class DF, class DU>
HWY_INLINE hn::Vec<DF> quarter_angle(DF df, DU du, hn::Vec<DU> w) {
  return hn::Mul(ch::uniform_open(df, du, w), hn::Set(df, 1.57079632679489661923f));
}

// cos(theta) on (0, pi / 2): the Taylor series to theta^12 errs by < 7e-9 there (below float's
// rounding).
template <class DF>
HWY_INLINE hn::Vec<DF> cos_quarter(DF df, hn::Vec<DF> theta) {
  const auto t = hn::Mul(theta, theta);
  return polyval(df, t, 1.0f / 479001600.0f, -1.0f / 3628800.0f, 1.0f / 40320.0f, -1.0f / 720.0f,
                 1.0f / 24.0f, -0.5f, 1.0f);
}

// cos(theta), theta uniform on (-pi, pi), from a word: cos of a uniform angle on (0, pi / 2)
// (the high 24 bits) with the sign of the lowest bit, which has the same distribution.
template <class DF, class DU>
HWY_INLINE hn::Vec<DF> cos_uniform(DF df, DU du, hn::Vec<DU> w) {
  const auto c = cos_quarter(df, quarter_angle(df, du, w));
  // The sign bit from the word's lowest bit.
  const auto sign = hn::BitCast(df, hn::ShiftLeft<31>(w));
  return hn::Xor(c, sign);
}

// sin(theta) on the same interval: the Taylor series to theta^13 errs by < 1e-9 there.
template <class DF>
HWY_INLINE hn::Vec<DF> sin_quarter(DF df, hn::Vec<DF> theta) {
  const auto t = hn::Mul(theta, theta);
  const auto s = polyval(df, t, 1.0f / 6227020800.0f, -1.0f / 39916800.0f, 1.0f / 362880.0f,
                         -1.0f / 5040.0f, 1.0f / 120.0f, -1.0f / 6.0f, 1.0f);
  return hn::Mul(s, theta);
}

// A unit phase e^(i phi), phi uniform on (-pi, pi], from a word: theta uniform on (0, pi / 2)
// from the high 24 bits, (cos theta, sin theta) reflected across the axes by bits 0 and 1 (the
// reflections of a uniform quarter turn cover the circle uniformly).
template <class DF, class DU>
HWY_INLINE void unit_phase(DF df, DU du, hn::Vec<DU> w, hn::Vec<DF>& c, hn::Vec<DF>& s) {
  const auto theta = quarter_angle(df, du, w);
  const auto sign_c = hn::BitCast(df, hn::ShiftLeft<31>(w));
  const auto sign_s = hn::BitCast(df, hn::And(hn::ShiftLeft<30>(w), hn::Set(du, 0x80000000U)));
  c = hn::Xor(cos_quarter(df, theta), sign_c);
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

// Samples per block: the block's float and word arrays (8 x 2 KiB) stay in L1 over the looks.
constexpr std::size_t kBlock = 512;

// One look's detected power p of a vector into acc: the first look stores (its amplitude for
// the mean detector), later looks add the amplitude or keep the maximum power.
template <class DF>
HWY_INLINE void accumulate_look(DF df, bool first_look, bool max_detector, hn::Vec<DF> p,
                                float* acc) {
  if (first_look) {
    hn::Store(max_detector ? p : hn::Sqrt(p), df, acc);
  } else if (max_detector) {
    hn::Store(hn::Max(hn::Load(df, acc), p), df, acc);
  } else {
    hn::Store(hn::Add(hn::Load(df, acc), hn::Sqrt(p)), df, acc);
  }
}

// The detector's output of a block from the accumulated looks acc[0, len): the maximum power,
// or the square of the mean amplitude, times `unscale`, in double.
HWY_INLINE void write_detected(const float* acc, std::size_t len, int looks, bool max_detector,
                               double unscale, double* out) {
  const hn::ScalableTag<double> dd;
  const hn::Rebind<float, decltype(dd)> dfh;
  const std::size_t Ld = hn::Lanes(dd);
  const double inv = 1.0 / static_cast<double>(looks);
  const std::size_t vlen = len / Ld * Ld;
  for (std::size_t i = 0; i < vlen; i += Ld) {
    auto v = hn::PromoteTo(dd, hn::LoadU(dfh, acc + i));
    if (!max_detector) {
      v = hn::Mul(v, hn::Set(dd, inv));
      v = hn::Mul(v, v);
    }
    hn::StoreU(hn::Mul(v, hn::Set(dd, unscale)), dd, out + i);
  }
  for (std::size_t i = vlen; i < len; ++i) {
    double v = static_cast<double>(acc[i]);
    if (!max_detector) {
      v *= inv;
      v *= v;
    }
    out[i] = v * unscale;
  }
}

}  // namespace sonarsynth::sensor_kernel::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // SONARSYNTH_SENSOR_KERNEL_BLOCKS_INL_H_ toggle
