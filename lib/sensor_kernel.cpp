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
#include "sonarsynth/sensor_kernel_blocks-inl.hpp"
#include "sonarsynth/sensor_kernel_filtered-inl.hpp"
// clang-format on

HWY_BEFORE_NAMESPACE();
namespace sonarsynth::sensor_kernel::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace ch = sonarsynth::counter_hash::HWY_NAMESPACE;

// Stream of the texture's Marsaglia–Tsang fallback beyond the tables (as in noise.cpp).
constexpr std::uint64_t kStreamTexture = 1u << 20;

// The exponent e of detect_impl's block scale 2^-e: even (the square roots of the mean detector
// scale exactly too, so that a sample's output does not depend on the other samples of its
// block), putting the largest finite power of the block (mean, thermal noise, floor) near 1.
HWY_INLINE int detect_block_exponent(const DetectorArgs& a, const double* base, const double* gain,
                                     std::size_t len) {
  const hn::ScalableTag<double> dd;
  const std::size_t Ld = hn::Lanes(dd);
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
  return top > 0.0 ? std::ilogb(top) & ~1 : 0;
}

// The block's scaled mean powers bg and thermal noise powers mg in float32, zero-padded to
// `padded`; true if some mean is > 0.
HWY_INLINE bool detect_block_powers(const DetectorArgs& a, const double* base, const double* gain,
                                    std::size_t len, std::size_t padded, double scale, float* bg,
                                    float* mg) {
  const hn::ScalableTag<double> dd;
  const hn::Rebind<float, decltype(dd)> dfh;
  const std::size_t Ld = hn::Lanes(dd);
  const std::size_t vlen = len / Ld * Ld;
  const auto th = hn::Set(dd, a.thermal_power);
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
  return any_mean;
}

// The speckled power of look ju of a vector of mean powers m: where the mean is > 0, m times the
// lattice's frozen power fld (where it applies; none if fld is null) or an Exp(1) draw of the
// speckle word hs; elsewhere m itself (shadow: 0; bad input: negative or NaN, kept so that the
// quantiser counts it).
template <class DF, class DU>
HWY_INLINE hn::Vec<DF> speckled_power(DF df, DU du, const counter_hash::Stream& ss, hn::Vec<DF> m,
                                      const float* fld, const std::uint32_t* hs, std::uint32_t ju) {
  const auto has_mean = hn::Gt(m, hn::Zero(df));
  if (hn::AllFalse(df, has_mean)) return m;
  if (fld == nullptr) {
    return hn::IfThenElse(has_mean,
                          hn::Mul(m, exp1(df, du, ch::draw(du, ss, hn::Load(du, hs), ju))), m);
  }
  const auto f = hn::Load(df, fld);
  const auto draw_here = hn::And(hn::IsNaN(f), has_mean);
  auto es = f;
  if (!hn::AllFalse(df, draw_here)) {
    es = hn::IfThenElse(draw_here, exp1(df, du, ch::draw(du, ss, hn::Load(du, hs), ju)), f);
  }
  return hn::IfThenElse(has_mean, hn::Mul(m, es), m);
}

// p plus the thermal noise of mean power mg (|s + n|^2 with the phase of n relative to s
// uniform: A + M E + 2 sqrt(A M E) cos) and the floor of power floor_v, drawn from the noise
// word hnw for look ju.
template <class DF, class DU>
HWY_INLINE hn::Vec<DF> add_receiver_noise(DF df, DU du, const counter_hash::Stream& sn,
                                          hn::Vec<DF> p, const float* mg, const std::uint32_t* hnw,
                                          std::uint32_t ju, bool thermal, bool floor,
                                          hn::Vec<DF> floor_v) {
  if (thermal) {
    const auto h = hn::Load(du, hnw);
    const auto me =
        hn::Mul(hn::Load(df, mg), exp1(df, du, ch::draw(du, sn, h, ju * kNoiseWordsPerLook)));
    const auto c = cos_uniform(df, du, ch::draw(du, sn, h, ju * kNoiseWordsPerLook + 1));
    const auto cross = hn::Mul(hn::Set(df, 2.0f), hn::Sqrt(hn::Mul(p, me)));
    p = hn::MulAdd(cross, c, hn::Add(p, me));
    p = hn::IfThenElse(hn::Lt(p, hn::Zero(df)), hn::Zero(df), p);  // rounding only: exactly >= 0
  }
  if (floor) {
    const auto h = hn::Load(du, hnw);
    p = hn::MulAdd(floor_v, exp1(df, du, ch::draw(du, sn, h, ju * kNoiseWordsPerLook + 2)), p);
  }
  return p;
}

void detect_impl(const DetectorArgs& a, counter_hash::Stream ss, counter_hash::Stream sn) {
  const hn::ScalableTag<float> df;
  const hn::RebindToUnsigned<decltype(df)> du;
  const std::size_t L = hn::Lanes(df);
  HWY_ALIGN float bg[kBlock], mg[kBlock], acc[kBlock], fld[kBlock];
  HWY_ALIGN std::uint32_t hs[kBlock], hnw[kBlock];
  const bool thermal = a.thermal_power > 0.0, floor = a.floor_power > 0.0;
  for (std::size_t b0 = 0; b0 < a.n; b0 += kBlock) {
    const std::size_t len = std::min(kBlock, a.n - b0);
    // Padded to whole vectors: the tail lanes compute on zeros and are not stored.
    const std::size_t padded = (len + L - 1) / L * L;
    // The block in float32 scaled by a power of two (exact, the same on every target) that
    // puts its largest finite power near 1: output powers span more than float's range
    // (amplitude output up to float's maximum is a power of 1e77).
    const double* base = a.base + b0;
    const double* gain = a.gain + b0;
    const int e = detect_block_exponent(a, base, gain, len);
    const bool any_mean =
        detect_block_powers(a, base, gain, len, padded, std::ldexp(1.0, -e), bg, mg);
    const auto floor_v = hn::Set(df, static_cast<float>(a.floor_power * std::ldexp(1.0, -e)));
    // Speckle key words only where a speckle draw may be needed (some mean > 0).
    if (any_mean) key_words(du, a.keys + b0, len, ss, hs);
    if (thermal || floor) key_words(du, a.noise_keys + b0, len, sn, hnw);
    const bool have_field = a.field != nullptr;
    for (int j = 0; j < a.looks; ++j) {
      const auto ju = static_cast<std::uint32_t>(j);
      if (have_field && any_mean) {
        const double* f = a.field + static_cast<std::size_t>(j) * a.n + b0;
        for (std::size_t i = 0; i < padded; ++i) fld[i] = i < len ? static_cast<float>(f[i]) : 0.0f;
      }
      for (std::size_t i = 0; i < padded; i += L) {
        auto p = speckled_power(df, du, ss, hn::Load(df, bg + i), have_field ? fld + i : nullptr,
                                hs + i, ju);
        p = add_receiver_noise(df, du, sn, p, mg + i, hnw + i, ju, thermal, floor, floor_v);
        accumulate_look(df, j == 0, a.max_detector, p, acc + i);
      }
    }
    write_detected(acc, len, a.looks, a.max_detector, std::ldexp(1.0, e), a.out + b0);
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
  FilteredBlock blk;
  const std::size_t K = a.taps_n / 2;
  float taps[2 * kMaxHalfTaps + 1];
  for (std::size_t k = 0; k < a.taps_n; ++k) taps[k] = static_cast<float>(a.taps[k]);
  const bool thermal = a.thermal_power > 0.0, floor = a.floor_power > 0.0;
  const bool lattice = a.field_norm != nullptr;
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
    const std::ptrdiff_t first = t0 + static_cast<std::ptrdiff_t>(u0);  // sample at u0
    const double* base = a.base + first;
    const double* norm = lattice ? a.field_norm + first : nullptr;
    const std::size_t cnt = u1 - u0;
    int ea = 0, eo = 0;
    filtered_exponents(a, base, a.gain + first, cnt, ea, eo);
    const bool any_mean =
        filtered_amplitudes(a, base, norm, ext, u0, u1, std::ldexp(1.0, -ea), blk);
    filtered_gain(a, b0, len, padded, std::ldexp(1.0, ea - eo), blk.gain);
    std::fill(blk.hs, blk.hs + ext + L, 0u);
    std::fill(blk.hnw, blk.hnw + ext + L, 0u);
    if (any_mean) key_words(du, a.keys + first, cnt, ss, blk.hs + u0);
    if (thermal || floor) key_words(du, a.noise_keys + first, cnt, sn, blk.hnw + u0);
    const auto floor_v = hn::Set(df, static_cast<float>(a.floor_power * std::ldexp(1.0, -eo)));
    for (int j = 0; j < a.looks; ++j) {
      const auto ju = static_cast<std::uint32_t>(j);
      if (lattice && any_mean) {
        const float* re = a.field_re + static_cast<std::size_t>(j) * a.field_stride;
        const float* im = a.field_im + static_cast<std::size_t>(j) * a.field_stride;
        std::fill(blk.fre, blk.fre + ext, 0.0f);
        std::fill(blk.fim, blk.fim + ext, 0.0f);
        std::copy(re + first, re + (t0 + static_cast<std::ptrdiff_t>(u1)), blk.fre + u0);
        std::copy(im + first, im + (t0 + static_cast<std::ptrdiff_t>(u1)), blk.fim + u0);
      }
      filtered_echo(df, du, ss, sn, ju, ext, lattice, thermal, blk);
      filtered_look(df, du, sn, ju, taps, a.taps_n, padded, floor, floor_v, a.max_detector, blk);
    }
    write_detected(blk.acc, len, a.looks, a.max_detector, std::ldexp(1.0, eo), a.out + b0);
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
