// SPDX-License-Identifier: MIT
// The patch textures' per-sample pass in vector form (sensor_mean_simd.hpp), compiled per Highway
// target (AVX-512, AVX2, EMU128) without floating-point contraction, so that every lane computes
// the scalar expression's value bit for bit.
#include "sonarsynth/sensor_mean_simd.hpp"

#include "sonarsynth/simd.hpp"

// clang-format off
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "lib/sensor_mean_simd.cpp"
#include <hwy/foreach_target.h>
#include <hwy/highway.h>
// clang-format on

HWY_BEFORE_NAMESPACE();
namespace sonarsynth::sensor_mean::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void add_textured(const double* level, const std::int64_t* cell, const double* wr,
                  const double* nodes, std::size_t from, std::size_t to, double* mean) {
  std::size_t i = from;
#if HWY_TARGET != HWY_SCALAR && HWY_TARGET != HWY_EMU128  // the portable targets: scalar loop
  const hn::ScalableTag<double> d;
  const hn::RebindToSigned<decltype(d)> di;
  const std::size_t lanes = hn::Lanes(d);
  const auto one = hn::Set(d, 1.0), hide = hn::Set(d, 1000.0);
  const auto next = hn::Set(di, 1);
  for (; i + lanes <= to; i += lanes) {
    const auto m = hn::LoadU(d, mean + i);
    const auto l = hn::LoadU(d, level + i);
    const auto c = hn::LoadU(di, cell + i);
    const auto w = hn::LoadU(d, wr + i);
    const auto lo = hn::GatherIndex(d, nodes, c);
    const auto hi = hn::GatherIndex(d, nodes, hn::Add(c, next));
    const auto tex = hn::Add(hn::Mul(hn::Sub(one, w), lo), hn::Mul(w, hi));
    const auto term = hn::IfThenElse(hn::Gt(m, hn::Mul(hide, l)), l, hn::Mul(l, tex));
    hn::StoreU(hn::Add(m, term), d, mean + i);
  }
#endif
  for (; i < to; ++i) {
    if (mean[i] > 1000.0 * level[i]) {
      mean[i] += level[i];
    } else {
      const auto c = static_cast<std::size_t>(cell[i]);
      mean[i] += level[i] * ((1.0 - wr[i]) * nodes[c] + wr[i] * nodes[c + 1]);
    }
  }
}

void blend_rows(const double* row0, const double* row1, double wa, std::size_t from, std::size_t to,
                double* out) {
  const hn::ScalableTag<double> d;
  const std::size_t lanes = hn::Lanes(d);
  const auto a = hn::Set(d, 1.0 - wa), b = hn::Set(d, wa);
  std::size_t c = from;
  for (; c + lanes <= to; c += lanes) {
    hn::StoreU(hn::Add(hn::Mul(a, hn::LoadU(d, row0 + c)), hn::Mul(b, hn::LoadU(d, row1 + c))), d,
               out + c);
  }
  for (; c < to; ++c) out[c] = (1.0 - wa) * row0[c] + wa * row1[c];
}

}  // namespace sonarsynth::sensor_mean::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace sonarsynth::sensor_mean {

HWY_EXPORT(add_textured);
HWY_EXPORT(blend_rows);

void add_textured(const double* level, const std::int64_t* cell, const double* wr,
                  const double* nodes, std::size_t from, std::size_t to, double* mean) {
  simd::configure_from_environment();
  HWY_DYNAMIC_DISPATCH(add_textured)(level, cell, wr, nodes, from, to, mean);
}

void blend_rows(const double* row0, const double* row1, double wa, std::size_t from, std::size_t to,
                double* out) {
  simd::configure_from_environment();
  HWY_DYNAMIC_DISPATCH(blend_rows)(row0, row1, wa, from, to, out);
}

}  // namespace sonarsynth::sensor_mean
#endif  // HWY_ONCE
