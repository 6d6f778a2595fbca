// SPDX-License-Identifier: MIT
// The threshold-free first-return reference of bench/bottom_track_real (docs/conversion.md) on
// synthetic sides whose onset is known by construction.
#include "first_return_change_point.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace bench {
namespace {

TEST(TwoLevelChangePoint, ExactOnANoiseFreeStep) {
  std::vector<double> x(50, 3.0);
  for (std::size_t i = 17; i < x.size(); ++i) x[i] = 11.0;
  EXPECT_EQ(two_level_change_point(x, 0, x.size()), 17u);
  EXPECT_EQ(two_level_change_point(x, 5, 30), 17u);
  EXPECT_EQ(two_level_change_point(x, 5, 8), 5u);  // too short to fit
}

/// A side: `pulse` bright samples, water speckle of mean `water` up to `onset`, then seabed
/// speckle whose mean rises from `seabed` at the onset by `rise_db` over the rest of the side
/// (linearly in dB), Rayleigh amplitude (exponential intensity) speckle throughout.
std::vector<float> side(std::size_t n, std::size_t onset, double rise_db, std::mt19937& rng,
                        double water = 3.0) {
  const double seabed = 30.0;
  std::exponential_distribution<double> speckle(1.0);
  std::vector<float> s(n);
  for (std::size_t i = 0; i < n; ++i) {
    double mean = water;
    if (i < 6) {
      mean = 1e5;
    } else if (i >= onset) {
      const double f = static_cast<double>(i - onset) / static_cast<double>(n - onset);
      mean = seabed * std::pow(10.0, rise_db * f / 20.0);
    }
    s[i] = static_cast<float>(mean * std::sqrt(speckle(rng)));
  }
  return s;
}

TEST(ChangePointFirstReturn, FindsTheOnsetInSpeckleWithinTwoSamples) {
  std::mt19937 rng(11);
  int within = 0;
  const int trials = 300;
  for (int t = 0; t < trials; ++t) {
    const std::size_t onset = 60 + static_cast<std::size_t>(t % 300);
    const std::vector<float> s = side(1000, onset, 0.0, rng);
    const std::ptrdiff_t c = change_point_first_return(s, 34);
    if (std::abs(c - static_cast<std::ptrdiff_t>(onset)) <= 2) ++within;
  }
  EXPECT_GE(within, trials * 95 / 100);
}

TEST(ChangePointFirstReturn, ASeabedBrighteningFarFromNadirDoesNotMoveTheOnset) {
  // A 12 dB step, then the seabed brightens by 30 dB over the side: one fit over the whole side
  // puts the change point up the slope; the window keeps it at the onset.
  std::mt19937 rng(12);
  int within = 0, whole_side_within = 0;
  const int trials = 200;
  for (int t = 0; t < trials; ++t) {
    const std::size_t onset = 100 + static_cast<std::size_t>(t % 200);
    const std::vector<float> s = side(1000, onset, 30.0, rng, 7.5);
    if (std::abs(change_point_first_return(s, 34) - static_cast<std::ptrdiff_t>(onset)) <= 2) {
      ++within;
    }
    if (std::abs(change_point_first_return(s, 1000) - static_cast<std::ptrdiff_t>(onset)) <= 2) {
      ++whole_side_within;
    }
  }
  // 12 dB of contrast in Rayleigh speckle (5.6 dB of spread per sample): the change point is
  // itself within 2 samples on about 92 % of the realisations.
  EXPECT_GE(within, trials * 90 / 100) << within;
  EXPECT_LT(whole_side_within, trials / 2) << whole_side_within;
}

TEST(ChangePointFirstReturn, NoPickOnAnEmptyOrZeroSide) {
  EXPECT_EQ(change_point_first_return(std::vector<float>{}, 34), -1);
  EXPECT_EQ(change_point_first_return(std::vector<float>(100, 0.0f), 34), -1);
  EXPECT_EQ(change_point_first_return(std::vector<float>(100, 1.0f), 1), -1);
}

}  // namespace
}  // namespace bench
