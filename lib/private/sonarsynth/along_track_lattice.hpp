// SPDX-License-Identifier: MIT
// The along-track scatterer lattice of along_track_speckle (docs/physics.md §1.6), per sample:
// what the looks of a sample share (sample_at) and one look's power (look_power), for
// along_track_speckle_looks and any pass that needs the lattice one sample at a time.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/sensor_effects.hpp"

namespace sonarsynth::lattice {

// Lattice step in units of the weight's standard deviation.
constexpr double kStep = 1.5;
// Salt of the along-track scatterer lattice.
constexpr std::uint64_t kFieldSalt = 0xa10e7a0c5ca77e45ULL;
// Look l adds l 2^56 to the pair index of its keyed words.
constexpr int kMaxLooks = 256;
constexpr std::uint64_t kLookStride = std::uint64_t{1} << 56;

// The lattice weights w_k(frac) = exp(-1.125 (k - 1 - frac)^2), k = 0 .. 3 (the two-way
// amplitude pattern at the scatterers around the ping, frac in [0, 1) the ping's position
// between lattice points), tabulated at frac = j / kSteps and interpolated linearly:
// |w''| <= 2.25, so the error is below 2.25 / (8 kSteps^2) = 4.3e-6 (the sample is normalised by
// the interpolated sum of w^2, so its mean stays exactly 1).
class Weights {
 public:
  static constexpr int kSteps = 256;
  static const Weights& get() {
    static const Weights table;
    return table;
  }
  // The four weights at `frac`.
  void at(double frac, double w[4]) const {
    const double x = frac * kSteps;
    auto j = static_cast<int>(x);
    j = j < 0 ? 0 : (j >= kSteps ? kSteps - 1 : j);
    const double t = x - j;
    const double* a = w_[j];
    const double* b = w_[j + 1];
    for (int k = 0; k < 4; ++k) w[k] = a[k] + t * (b[k] - a[k]);
  }

 private:
  Weights() {
    for (int j = 0; j <= kSteps; ++j) {
      const double frac = static_cast<double>(j) / kSteps;
      for (int k = 0; k < 4; ++k) {
        const double d = k - 1 - frac;
        w_[j][k] = std::exp(-1.125 * d * d);
      }
    }
  }
  double w_[kSteps + 1][4];
};

// What the looks of one sample share: the weights (as float), the normalisation, the sample's
// range-cell word, the first scatterer pair and its parity.
struct Sample {
  float wf[4];
  double inv_2w2;
  std::uint64_t cell, pair0;
  unsigned shift;  // 32 when the first scatterer is the high half of its pair's word, else 0
};

// The keyed word of the lattice line (survey line and side).
inline std::uint64_t line_word(const AlongTrackField& f) {
  return hash_combine(splitmix64(f.seed ^ kFieldSalt), f.key);
}

// Sample i's shared part; false where the speckle is drawn independently instead: below the
// first return, where consecutive pings are more than 2.5 footprints (r beta_eff = 1.77 sw)
// apart (correlation < 1e-4), and where the lattice index would not fit an integer (a
// degenerate beam or position).
inline bool sample_at(const AlongTrackField& f, const AlongTrackTable& table, std::uint64_t line,
                      const Weights& weights, std::size_t i, Sample& s) {
  const double sw = table.sw[i];
  // u = along-track position in lattice steps of 1.5 sw (sw = r theta / sqrt(8 ln 2)).
  const double u = f.along_track_m * table.inv_step[i];
  if (i < f.first_sample || f.ping_spacing_m > 4.43 * sw || !(std::abs(u) < 1e15)) return false;
  // Lattice step 1.5 sw: the lattice sum reproduces the continuous one to ~1e-4 (Poisson
  // summation, 2 exp(-2 pi^2 / 1.5^2)); four scatterers span the weights above e^-4.5.
  auto m0 = static_cast<std::int64_t>(u);  // floor(u), |u| < 1e15
  if (static_cast<double>(m0) > u) --m0;
  const double frac = u - static_cast<double>(m0);
  double w[4];
  weights.at(frac, w);
  // The sum in float (relative rounding ~1e-7, far below the speckle's own spread), normalised
  // in double by 1 / (2 sum w^2) of the same float weights (the scatterers
  // (g1 + i g2) / sqrt(2) have unit power), so the mean stays exactly 1.
  double w2 = 0.0;
  for (int k = 0; k < 4; ++k) {
    s.wf[k] = static_cast<float>(w[k]);
    w2 += static_cast<double>(s.wf[k]) * static_cast<double>(s.wf[k]);
  }
  s.inv_2w2 = 0.5 / w2;
  const std::int64_t first = m0 - 1;
  s.shift = static_cast<unsigned>(first & 1) * 32;
  // The keyed word of (sample i, look, pair p of scatterers m = 2p, 2p + 1) is
  // wyrand_stream(cell, p + look 2^56), cell = splitmix_stream(line, i): |p| < 2^49, so (p, look)
  // pairs are distinct for look < 2^8.
  s.cell = splitmix_stream(line, static_cast<std::uint64_t>(i));
  s.pair0 = static_cast<std::uint64_t>(first >> 1);
  return true;
}

// The unnormalised complex sum of `look` at the sample. Scatterer m (lattice index m0 - 1 + k):
// g1 from the low 16 bits of one half of the word of the pair m >> 1, g2 from its high 16 bits
// (NormalTable): two words per sample, three when m0 - 1 is odd. The four scatterers' halves
// are the 128 bits of the words from bit `shift` on.
inline void look_sum(const Sample& s, std::uint64_t look, const NormalTable& normal, float& re,
                     float& im) {
  const std::uint64_t p0 = s.pair0 + look * kLookStride;
  const std::uint64_t h0 = wyrand_stream(s.cell, p0);
  const std::uint64_t h1 = wyrand_stream(s.cell, p0 + 1);
  const std::uint64_t h2 = s.shift != 0 ? wyrand_stream(s.cell, p0 + 2) : 0;
  const std::uint64_t keep = std::uint64_t{0} - (s.shift >> 5);  // all ones when shifted
  const std::uint64_t lo = (h0 >> s.shift) | ((h1 << 32) & keep);
  const std::uint64_t hi = (h1 >> s.shift) | ((h2 << 32) & keep);
  const auto half = [&](int k) {
    return static_cast<std::uint32_t>((k < 2 ? lo : hi) >> (32 * (k & 1)));
  };
  re = 0.0f;
  im = 0.0f;
  for (int k = 0; k < 4; ++k) {
    const std::uint32_t b = half(k);
    re += s.wf[k] * normal(b);
    im += s.wf[k] * normal(b >> 16);
  }
}

// The unit-mean speckle power of `look` at the sample.
inline double look_power(const Sample& s, std::uint64_t look, const NormalTable& normal) {
  float re, im;
  look_sum(s, look, normal, re, im);
  const auto dre = static_cast<double>(re), dim = static_cast<double>(im);
  return (dre * dre + dim * dim) * s.inv_2w2;
}

// The same look as a complex field of unit mean power (re^2 + im^2 = look_power), for the range
// filter of the sensor stage, which needs the phase too.
inline void look_field(const Sample& s, std::uint64_t look, const NormalTable& normal, double& re,
                       double& im) {
  float fre, fim;
  look_sum(s, look, normal, fre, fim);
  const double g = std::sqrt(s.inv_2w2);
  re = static_cast<double>(fre) * g;
  im = static_cast<double>(fim) * g;
}

}  // namespace sonarsynth::lattice
