// SPDX-License-Identifier: MIT
// The stages of the range-filtered detector's vector kernel (filtered_impl of
// lib/sensor_kernel.cpp) on one block: the scales, the amplitudes, the gain, the complex echo and
// the filtered look (per target: include after hwy/highway.h in a file compiled through
// hwy/foreach_target.h).
#if defined(SONARSYNTH_SENSOR_KERNEL_FILTERED_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SONARSYNTH_SENSOR_KERNEL_FILTERED_INL_H_
#undef SONARSYNTH_SENSOR_KERNEL_FILTERED_INL_H_
#else
#define SONARSYNTH_SENSOR_KERNEL_FILTERED_INL_H_
#endif

#include <hwy/highway.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "sonarsynth/counter_hash-inl.hpp"
#include "sonarsynth/counter_hash.hpp"
#include "sonarsynth/sensor_kernel.hpp"
#include "sonarsynth/sensor_kernel_blocks-inl.hpp"

HWY_BEFORE_NAMESPACE();
namespace sonarsynth::sensor_kernel::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace ch = sonarsynth::counter_hash::HWY_NAMESPACE;

// The float32 buffers of one block of filtered_impl: the block and a halo of K samples each side
// (ext), with room for the padding to whole vectors.
struct FilteredBlock {
  static constexpr std::size_t kExt = kBlock + 2 * kMaxHalfTaps + 64;
  HWY_ALIGN float amp[kExt], amp_field[kExt], amp_thermal[kExt], zr[kExt], zi[kExt];
  HWY_ALIGN float fre[kExt], fim[kExt], gain[kBlock], acc[kBlock];
  HWY_ALIGN std::uint32_t hs[kExt], hnw[kExt];
};

// The exponents of filtered_impl's two scales (even): ea of the amplitudes from the largest mean
// power (and thermal power) of block and halo, eo of the output powers from the largest of mean
// and noise powers times the gain, and the floor. base and gn from the first sample of the halo
// inside the record, cnt samples.
HWY_INLINE void filtered_exponents(const FilteredArgs& a, const double* base, const double* gn,
                                   std::size_t cnt, int& ea, int& eo) {
  const hn::ScalableTag<double> dd;
  const std::size_t Ld = hn::Lanes(dd);
  const std::size_t vcnt = cnt / Ld * Ld;
  double top_a = a.thermal_power, top_o = a.floor_power;
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
  for (std::size_t u = vcnt; u < cnt; ++u) {
    const double b = base[u];
    if (b > 0.0 && std::isfinite(b)) top_a = std::max(top_a, b);
    for (const double v : {b * gn[u], a.thermal_power * gn[u]}) {
      if (std::isfinite(v)) top_o = std::max(top_o, v);
    }
  }
  ea = top_a > 0.0 ? std::ilogb(top_a) & ~1 : 0;
  eo = top_o > 0.0 ? std::ilogb(top_o) & ~1 : 0;
}

// The block's scaled mean amplitudes (amp; amp_field: times the lattice's norm) and thermal
// amplitude over ext [0, ext), zero outside the record's [u0, u1); true if some mean is > 0.
HWY_INLINE bool filtered_amplitudes(const FilteredArgs& a, const double* base, const double* norm,
                                    std::size_t ext, std::size_t u0, std::size_t u1, double sa2,
                                    FilteredBlock& blk) {
  const hn::ScalableTag<double> dd;
  const hn::Rebind<float, decltype(dd)> dfh;
  const std::size_t Ld = hn::Lanes(dd);
  const std::size_t cnt = u1 - u0;
  const std::size_t vcnt = cnt / Ld * Ld;
  const bool lattice = norm != nullptr;
  const auto sa2_v = hn::Set(dd, sa2);
  const auto zero_d = hn::Zero(dd);
  std::fill(blk.amp, blk.amp + ext, 0.0f);
  std::fill(blk.amp_field, blk.amp_field + ext, 0.0f);
  std::fill(blk.amp_thermal, blk.amp_thermal + ext, 0.0f);
  std::fill(blk.amp_thermal + u0, blk.amp_thermal + u1,
            static_cast<float>(std::sqrt(a.thermal_power * sa2)));
  auto any_v = hn::Zero(dd);
  for (std::size_t u = 0; u < vcnt; u += Ld) {
    const auto b = hn::LoadU(dd, base + u);
    const auto has = hn::Gt(b, zero_d);
    const auto bs = hn::IfThenElseZero(has, hn::Mul(b, sa2_v));
    any_v = hn::Max(any_v, bs);
    hn::StoreU(hn::DemoteTo(dfh, hn::Sqrt(bs)), dfh, blk.amp + u0 + u);
    if (lattice) {
      const auto fa = hn::IfThenElseZero(has, hn::Sqrt(hn::Mul(hn::LoadU(dd, norm + u), bs)));
      hn::StoreU(hn::DemoteTo(dfh, fa), dfh, blk.amp_field + u0 + u);
    }
  }
  bool any_mean = hn::GetLane(hn::MaxOfLanes(dd, any_v)) > 0.0;
  for (std::size_t u = vcnt; u < cnt; ++u) {
    const double b = base[u];
    if (!(b > 0.0)) continue;
    any_mean = true;
    blk.amp[u0 + u] = static_cast<float>(std::sqrt(b * sa2));
    if (lattice) blk.amp_field[u0 + u] = static_cast<float>(std::sqrt(norm[u] * (b * sa2)));
  }
  return any_mean;
}

// The block's output gain [0, padded): gain_i 2^(ea - eo) / w2_i, w2_i the power of the taps
// inside the record (1 away from its ends), zero past len.
HWY_INLINE void filtered_gain(const FilteredArgs& a, std::size_t b0, std::size_t len,
                              std::size_t padded, double g_scale, float* gain) {
  const hn::ScalableTag<double> dd;
  const hn::Rebind<float, decltype(dd)> dfh;
  const std::size_t Ld = hn::Lanes(dd);
  const std::size_t K = a.taps_n / 2;
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
}

// The complex echo (zr, zi) of look ju over ext: the lattice's frozen field where it applies
// (lattice), else a speckle draw (Rayleigh amplitude, uniform phase) where the mean is > 0, plus
// the thermal noise's complex draw (thermal).
template <class DF, class DU>
HWY_INLINE void filtered_echo(DF df, DU du, const counter_hash::Stream& ss,
                              const counter_hash::Stream& sn, std::uint32_t ju, std::size_t ext,
                              bool lattice, bool thermal, FilteredBlock& blk) {
  const std::size_t L = hn::Lanes(df);
  const auto zero = hn::Zero(df);
  for (std::size_t u = 0; u < ext; u += L) {
    auto r = zero, i = zero;
    const auto am = hn::Load(df, blk.amp + u);
    const auto has = hn::Gt(am, zero);
    if (!hn::AllFalse(df, has)) {
      auto draw_here = has;
      if (lattice) {
        const auto af = hn::Load(df, blk.amp_field + u);
        const auto fr = hn::Mul(hn::Load(df, blk.fre + u), af);
        const auto fi = hn::Mul(hn::Load(df, blk.fim + u), af);
        const auto use = hn::And(has, hn::Not(hn::IsNaN(fr)));
        r = hn::IfThenElseZero(use, fr);
        i = hn::IfThenElseZero(use, fi);
        draw_here = hn::AndNot(use, has);
      }
      if (!hn::AllFalse(df, draw_here)) {
        const auto h = hn::Load(du, blk.hs + u);
        const auto ra = hn::Mul(hn::Sqrt(exp1(df, du, ch::draw(du, ss, h, ju))), am);
        hn::Vec<DF> c, s;
        unit_phase(df, du, ch::draw(du, ss, h, kPhaseCounter + ju), c, s);
        r = hn::IfThenElse(draw_here, hn::Mul(ra, c), r);
        i = hn::IfThenElse(draw_here, hn::Mul(ra, s), i);
      }
    }
    if (thermal) {
      const auto h = hn::Load(du, blk.hnw + u);
      const auto ra = hn::Mul(hn::Sqrt(exp1(df, du, ch::draw(du, sn, h, ju * kNoiseWordsPerLook))),
                              hn::Load(df, blk.amp_thermal + u));
      hn::Vec<DF> c, s;
      unit_phase(df, du, ch::draw(du, sn, h, ju * kNoiseWordsPerLook + 1), c, s);
      r = hn::MulAdd(ra, c, r);
      i = hn::MulAdd(ra, s, i);
    }
    hn::Store(r, df, blk.zr + u);
    hn::Store(i, df, blk.zi + u);
  }
}

// Look ju of the block's outputs [0, padded): the taps as a FIR over the complex echo, its power
// times the gain, plus the floor (floor), into the detector's accumulator.
template <class DF, class DU>
HWY_INLINE void filtered_look(DF df, DU du, const counter_hash::Stream& sn, std::uint32_t ju,
                              const float* taps, std::size_t taps_n, std::size_t padded, bool floor,
                              hn::Vec<DF> floor_v, bool max_detector, FilteredBlock& blk) {
  const std::size_t L = hn::Lanes(df);
  const std::size_t K = taps_n / 2;
  for (std::size_t o = 0; o < padded; o += L) {
    auto yr = hn::Zero(df), yi = hn::Zero(df);
    for (std::size_t k = 0; k < taps_n; ++k) {
      const auto h = hn::Set(df, taps[k]);
      yr = hn::MulAdd(h, hn::LoadU(df, blk.zr + o + k), yr);
      yi = hn::MulAdd(h, hn::LoadU(df, blk.zi + o + k), yi);
    }
    auto p = hn::Mul(hn::MulAdd(yr, yr, hn::Mul(yi, yi)), hn::Load(df, blk.gain + o));
    if (floor) {
      const auto h = hn::LoadU(du, blk.hnw + o + K);
      p = hn::MulAdd(floor_v, exp1(df, du, ch::draw(du, sn, h, ju * kNoiseWordsPerLook + 2)), p);
    }
    accumulate_look(df, ju == 0, max_detector, p, blk.acc + o);
  }
}

}  // namespace sonarsynth::sensor_kernel::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // SONARSYNTH_SENSOR_KERNEL_FILTERED_INL_H_ toggle
