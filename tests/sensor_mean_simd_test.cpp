// SPDX-License-Identifier: MIT
// The patch textures' per-sample pass in vector form (lib/sensor_mean_simd.cpp) against the
// scalar loop it replaces (nodes interpolated in range, the term at its mean where the echo is 30
// dB above it): bit for bit on every instruction set, at the threshold, for NaN echoes and for
// ranges that are not a multiple of the vector.
#include "sonarsynth/sensor_mean_simd.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/simd.hpp"

namespace sonarsynth {
namespace {

namespace simd = sonarsynth::simd;

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

double uniform(std::uint64_t& s) {
  s = splitmix64(s);
  return static_cast<double>(s >> 11) * 0x1p-53;
}

TEST(SensorMeanSimd, TexturedPassEqualsTheScalarLoopOnEveryTarget) {
  for (const double inv_patch : {1.0, 0.25, 0.37, 0.9999}) {
    const std::size_t n = 1037;
    std::uint64_t s = 7;
    std::vector<double> level(n), wr(n), mean0(n);
    std::vector<std::int64_t> cell(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double ur = (static_cast<double>(i) + 0.5) * inv_patch;
      cell[i] = static_cast<std::int64_t>(std::floor(ur));
      wr[i] = ur - std::floor(ur);
      level[i] = 1e-3 * (0.5 + uniform(s));
      // Echoes below, at and above 1000 x the term, and NaN.
      const int k = static_cast<int>(i % 6);
      mean0[i] = k == 0   ? 1000.0 * level[i]
                 : k == 1 ? std::nextafter(1000.0 * level[i], 1e300)
                 : k == 2 ? std::nan("")
                          : 2000.0 * level[i] * uniform(s);
    }
    const auto cells = static_cast<std::size_t>(cell[n - 1]) + 2;
    std::vector<double> row0(cells), row1(cells);
    for (std::size_t c = 0; c < cells; ++c) {
      row0[c] = 3.0 * uniform(s);
      row1[c] = 3.0 * uniform(s);
    }
    const double wa = 0.3 + 0.1 * inv_patch;
    for (const auto& [from, to] : {std::pair<std::size_t, std::size_t>{0, n}, {5, 1030}, {3, 9}}) {
      // The scalar loop of the mean terms: nodes per range patch, linear in range between them.
      std::vector<double> expected = mean0;
      for (std::size_t i = from; i < to; ++i) {
        if (expected[i] > 1000.0 * level[i]) {
          expected[i] += level[i];
          continue;
        }
        const auto c = static_cast<std::size_t>(cell[i]);
        const double lo = (1.0 - wa) * row0[c] + wa * row1[c];
        const double hi = (1.0 - wa) * row0[c + 1] + wa * row1[c + 1];
        expected[i] += level[i] * ((1.0 - wr[i]) * lo + wr[i] * hi);
      }
      for (const auto t : simd::supported_targets()) {
        simd::set_target(t);
        std::vector<double> nodes(cells, -1.0);
        const auto c0 = static_cast<std::size_t>(cell[from]);
        const auto c1 = static_cast<std::size_t>(cell[to - 1]) + 2;
        sensor_mean::blend_rows(row0.data(), row1.data(), wa, c0, c1, nodes.data());
        std::vector<double> mean = mean0;
        sensor_mean::add_textured(level.data(), cell.data(), wr.data(), nodes.data(), from, to,
                                  mean.data());
        for (std::size_t i = 0; i < n; ++i) {
          ASSERT_TRUE(same_bits(mean[i], expected[i]))
              << simd::target_name(t) << " inv_patch " << inv_patch << " [" << from << ", " << to
              << ") sample " << i << ": " << mean[i] << " vs " << expected[i];
        }
      }
    }
  }
  simd::set_target(simd::Target::automatic);
}

}  // namespace
}  // namespace sonarsynth
