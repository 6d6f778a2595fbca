// SPDX-License-Identifier: MIT
// Synthetic records with known statistics for the realism measure tests (bench/realism_stats.hpp):
// a fixed-seed draw, pings of a planted water column and Rayleigh speckle.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

#include "realism_stats.hpp"

namespace realism_test {

namespace rs = bench::realism;
using rs::Side;

constexpr double kPi = std::numbers::pi;
inline const double kRayleighContrast = std::sqrt(4.0 / kPi - 1.0);                    // 0.5227
inline const double kRayleighDbStd = 10.0 / std::log(10.0) * kPi / std::sqrt(24.0);    // 2.785 dB
inline const double kExponentialDbStd = 10.0 / std::log(10.0) * kPi / std::sqrt(6.0);  // 5.570 dB

/// Uniform (0, 1], Rayleigh and normal draws from a fixed-seed engine (the standard
/// distributions are implementation-defined; these are not).
class Draw {
 public:
  explicit Draw(std::uint64_t seed) : gen_(seed) {}
  double uniform() { return (static_cast<double>(gen_() >> 11) + 1.0) * 0x1.0p-53; }
  double rayleigh(double sigma) { return sigma * std::sqrt(-2.0 * std::log(uniform())); }
  double exponential(double mean) { return -mean * std::log(uniform()); }
  double normal() {
    return std::sqrt(-2.0 * std::log(uniform())) * std::cos(2.0 * kPi * uniform());
  }

 private:
  std::mt19937_64 gen_;
};

constexpr std::size_t kSamples = 1000;
constexpr double kRangeM = 100.0;  // 0.1 m per sample
constexpr double kDr = kRangeM / static_cast<double>(kSamples);

/// `count` pings of kSamples per side; value(k, i, side) fills them, altitude = altitude(k).
inline std::vector<rs::Ping> make_pings(
    std::size_t count, const std::function<float(std::size_t, std::size_t, Side)>& value,
    const std::function<double(std::size_t)>& altitude = {}) {
  std::vector<rs::Ping> pings(count);
  for (std::size_t k = 0; k < count; ++k) {
    rs::Ping& p = pings[k];
    p.slant_range_m = kRangeM;
    p.altitude_m = altitude ? altitude(k) : 0.0;
    p.port.resize(kSamples);
    p.starboard.resize(kSamples);
    for (std::size_t i = 0; i < kSamples; ++i) {
      p.port[i] = value(k, i, Side::kPort);
      p.starboard[i] = value(k, i, Side::kStarboard);
    }
  }
  return pings;
}

constexpr float kWater = 20.0f;       // 26.0 dB
constexpr std::size_t kBottom = 100;  // first seabed sample (r0 = 10.05 m)

/// Water column kWater, then iid Rayleigh(sigma) amplitudes from kBottom on.
inline std::vector<rs::Ping> rayleigh_record(std::size_t count, double sigma, std::uint64_t seed) {
  Draw d(seed);
  return make_pings(count, [&](std::size_t, std::size_t i, Side) {
    return i < kBottom ? kWater : static_cast<float>(d.rayleigh(sigma));
  });
}

}  // namespace realism_test
