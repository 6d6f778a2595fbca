// SPDX-License-Identifier: MIT
// The speckle keys of a ping side in vector form (lib/sample_keys.cpp): every instruction set
// gives the scalar functions' keys bit for bit, at cell boundaries, for negative indices, beyond
// the packed range and for lengths that are not a multiple of the vector.
#include "sonarsynth/sample_keys.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

#include "sonarsynth/simd.hpp"

namespace sonarsynth {
namespace {

namespace simd = sonarsynth::simd;

TEST(SampleKeys, PingKeysAreTheScalarHashOnEveryTarget) {
  std::vector<std::uint64_t> sh(61);
  for (std::size_t i = 0; i < sh.size(); ++i) sh[i] = splitmix64(i);
  const std::uint64_t h = hash_combine(1234567, 1);
  for (const auto t : simd::supported_targets()) {
    simd::set_target(t);
    for (const std::size_t n : {0u, 1u, 3u, 8u, 17u, 61u}) {
      std::vector<std::uint64_t> keys(n, 0);
      sample_keys::ping_keys(h, sh.data(), n, keys.data());
      for (std::size_t i = 0; i < n; ++i) {
        // The key of (ping, side, sample): bit 63 | hash_combine(hash_combine(ping, side), i) >> 1.
        ASSERT_EQ(keys[i], (1ULL << 63) | (hash_combine(h, i) >> 1))
            << simd::target_name(t) << " n " << n << " i " << i;
      }
    }
  }
  simd::set_target(simd::Target::automatic);
}

TEST(SampleKeys, GroundCellKeysAreTheScalarKeysOnEveryTarget) {
  // Cells of 0.25 m (inv_cell 4): ground ranges on cell edges (exact quarters), between them,
  // negative, near and beyond the packed range (2^22 cells in x and y, 2^15 in z).
  sample_keys::CellFrame f;
  f.nx = 12.5;
  f.ny = -7.25;
  f.dx = 0.6;
  f.dy = -0.8;
  f.inv_cell = 4.0;
  std::vector<SampleClass> cls;
  std::vector<double> gy, gz;
  std::vector<std::uint64_t> noise;
  std::uint64_t s = 99;
  for (int k = 0; k < 1999; ++k) {
    s = splitmix64(s);
    const double u = static_cast<double>(s >> 11) * 0x1p-53;
    double y = 0.0, z = 0.0;
    switch (k % 7) {
      case 0:
        y = 0.25 * (k - 1000);
        z = -0.25 * k;
        break;  // cell edges
      case 1:
        y = 150.0 * (u - 0.5);
        z = -30.0 + u;
        break;  // inside cells
      case 2:
        y = 1747600.0 + 40.0 * u;
        z = -5.0;
        break;  // x across 2^22 cells
      case 3:
        y = -1310720.0 - 10.0 * u;
        z = 3.0;
        break;  // y across -2^22 cells
      case 4:
        y = 20.0 * u;
        z = -8192.0 + 0.5 * (u - 0.5);
        break;  // z near -2^15 cells
      case 5:
        y = -20.0 * u;
        z = 8191.5 + u;
        break;  // z near 2^15 cells
      default:
        y = 1e-300 * (u - 0.5);
        z = -0.0;
        break;  // around zero
    }
    const auto c = static_cast<SampleClass>((k / 3) % 5);
    cls.push_back(c);
    gy.push_back(c == SampleClass::seabed || c == SampleClass::object ? y : std::nan(""));
    gz.push_back(c == SampleClass::seabed || c == SampleClass::object ? z : std::nan(""));
    noise.push_back(splitmix64(s ^ 0x5555));
  }
  std::size_t packed = 0, chained = 0;
  for (const auto t : simd::supported_targets()) {
    simd::set_target(t);
    for (const std::size_t n : {cls.size(), std::size_t{13}, std::size_t{5}}) {
      std::vector<std::uint64_t> keys(n);
      sample_keys::ground_cell_keys(f, cls.data(), gy.data(), gz.data(), noise.data(), n,
                                    keys.data());
      for (std::size_t i = 0; i < n; ++i) {
        const bool ground = cls[i] == SampleClass::seabed || cls[i] == SampleClass::object;
        const std::uint64_t expected =
            ground ? sample_keys::ground_cell_key_at(f, gy[i], gz[i]) : noise[i];
        ASSERT_EQ(keys[i], expected) << simd::target_name(t) << " sample " << i;
        if (ground && t == simd::Target::scalar && n == cls.size()) {
          ++((expected >> 62) == 1 ? packed : chained);
        }
      }
    }
    // In place (keys over the noise keys).
    std::vector<std::uint64_t> io = noise;
    sample_keys::ground_cell_keys(f, cls.data(), gy.data(), gz.data(), io.data(), io.size(),
                                  io.data());
    std::vector<std::uint64_t> keys(noise.size());
    sample_keys::ground_cell_keys(f, cls.data(), gy.data(), gz.data(), noise.data(), noise.size(),
                                  keys.data());
    EXPECT_EQ(io, keys) << simd::target_name(t);
  }
  simd::set_target(simd::Target::automatic);
  EXPECT_GT(packed, 300u);  // both forms of the key were exercised
  EXPECT_GT(chained, 100u);
}

TEST(SampleKeys, DistinctCellsInThePackedRangeHaveDistinctKeys) {
  std::set<std::uint64_t> seen;
  for (std::int64_t ix : {-4194304LL, -1LL, 0LL, 1LL, 4194303LL}) {
    for (std::int64_t iy = -40; iy < 40; ++iy) {
      for (std::int64_t iz : {-32768LL, -1LL, 0LL, 32767LL}) {
        const std::uint64_t k = sample_keys::ground_cell_key(ix, iy, iz);
        EXPECT_EQ(k >> 62, 1u);
        EXPECT_TRUE(seen.insert(k).second) << ix << " " << iy << " " << iz;
      }
    }
  }
}

}  // namespace
}  // namespace sonarsynth
