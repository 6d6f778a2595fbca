// SPDX-License-Identifier: MIT
// The first-return detector, the along-track tracker, the altitude choice and the across-track
// gain normalisation on synthetic pings whose truth is known by construction.
#include "sonarsynth/bottom_track.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace {

/// n samples: transmit pulse in the first `pulse` samples (bright), water (`water`) up to sample
/// `bottom`, then seabed speckle (exponential amplitude of mean `seabed`).
std::vector<float> side(std::size_t n, std::size_t bottom, std::mt19937& rng, double water = 2.0,
                        double seabed = 100.0, std::size_t pulse = 3) {
  std::exponential_distribution<double> speckle(1.0);
  std::uniform_real_distribution<double> noise(0.5, 1.5);
  std::vector<float> s(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (i < pulse) {
      s[i] = 5000.0f;
    } else if (i < bottom) {
      s[i] = static_cast<float>(water * noise(rng));
    } else {
      s[i] = static_cast<float>(seabed * speckle(rng));
    }
  }
  return s;
}

TEST(FirstReturnSample, FindsTheStepWithinTwoSamplesOverManySpeckleRealisations) {
  std::mt19937 rng(7);
  int within = 0;
  const int trials = 400;
  for (int t = 0; t < trials; ++t) {
    const std::size_t bottom = 40 + static_cast<std::size_t>(t % 200);
    const std::vector<float> s = side(1000, bottom, rng);
    const std::ptrdiff_t i = first_return_sample(s);
    ASSERT_GE(i, 0);
    if (std::abs(i - static_cast<std::ptrdiff_t>(bottom)) <= 2) ++within;
  }
  // Exponential speckle: a few dark seabed samples right after the step can delay the crossing.
  EXPECT_GE(within, trials * 95 / 100);
}

TEST(FirstReturnSample, LeadingEdgeFindsTheStepBeforeASeabedThatBrightensWithRange) {
  // The Iver2 shape (docs/conversion.md): a step of 12 dB out of the water, then a seabed that
  // brightens by 30 dB (linearly in dB) over the rest of the side, Rayleigh speckle. The side's
  // seabed percentile is the bright far seabed, so the threshold crossing falls up the slope;
  // the leading edge between the local levels does not.
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> noise(0.5, 1.5);
  std::exponential_distribution<double> intensity(1.0);
  BottomTrackOptions crossing;
  crossing.leading_edge = false;
  int edge_within = 0, crossing_within = 0;
  const int trials = 400;
  for (int t = 0; t < trials; ++t) {
    const std::size_t n = 1000, bottom = 60 + static_cast<std::size_t>(t % 300);
    std::vector<float> s(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (i < 3) {
        s[i] = 5000.0f;
      } else if (i < bottom) {
        s[i] = static_cast<float>(2.0 * noise(rng));
      } else {
        const double f = static_cast<double>(i - bottom) / static_cast<double>(n - bottom);
        s[i] = static_cast<float>(8.0 * std::pow(10.0, 1.5 * f) * std::sqrt(intensity(rng)));
      }
    }
    const auto b = static_cast<std::ptrdiff_t>(bottom);
    if (std::abs(first_return_sample(s) - b) <= 2) ++edge_within;
    if (std::abs(first_return_sample(s, crossing) - b) <= 2) ++crossing_within;
  }
  EXPECT_GE(edge_within, trials * 95 / 100) << edge_within;
  EXPECT_LT(crossing_within, trials * 80 / 100) << crossing_within;
}

TEST(FirstReturnSample, NoContrastOrTooShortGivesNoPick) {
  const std::vector<float> flat(500, 1.0f);
  EXPECT_EQ(first_return_sample(flat), -1);
  const std::vector<float> zeros(500, 0.0f);
  EXPECT_EQ(first_return_sample(zeros), -1);
  const std::vector<float> tiny(6, 1.0f);
  EXPECT_EQ(first_return_sample(tiny), -1);
}

TEST(FirstReturnSample, IgnoresASpikeInTheWaterColumn) {
  std::mt19937 rng(3);
  std::vector<float> s = side(800, 300, rng);
  for (std::size_t i = 120; i < 123; ++i) s[i] = 3000.0f;  // a fish: shorter than the hold
  const std::ptrdiff_t i = first_return_sample(s);
  EXPECT_NEAR(static_cast<double>(i), 300.0, 2.0);
}

TEST(BottomTracker, AlongTrackMedianReplacesOutliersAndMissingPicks) {
  std::mt19937 rng(11);
  BottomTracker tracker;
  const std::size_t n = 600;
  const double range_m = 30.0, dr = range_m / static_cast<double>(n);
  std::vector<std::size_t> truth;
  for (int k = 0; k < 100; ++k) {
    const std::size_t b = 150 + static_cast<std::size_t>(k / 4);  // a gentle rise of the seabed
    truth.push_back(b);
    std::vector<float> p = side(n, b, rng), s = side(n, b, rng);
    if (k == 30) std::fill(s.begin(), s.begin() + 60, 4000.0f);  // a long false early return
    if (k == 50) p.assign(n, 1.0f);                              // port without contrast
    if (k == 51) s.clear();                                      // starboard missing
    tracker.add_ping(p, s, range_m);
  }
  const std::vector<double> alt = tracker.altitudes_m();
  ASSERT_EQ(alt.size(), 100u);
  for (std::size_t k = 0; k < alt.size(); ++k) {
    EXPECT_NEAR(alt[k], (static_cast<double>(truth[k]) + 0.5) * dr, 2.0 * dr) << "ping " << k;
  }
}

TEST(ChooseAltitude, AutoKeepsAnAgreeingHeaderAndReplacesAZeroOrWrongOne) {
  const double dr = 0.03;
  const AltitudeChoice agree = choose_altitude(AltitudeSource::kAuto, 5.0, 5.05, dr);
  EXPECT_EQ(agree.altitude_m, 5.0);
  EXPECT_FALSE(agree.tracked);
  // Tolerance max(4 dr, 5 % of tracked) = max(0.12, 0.25) = 0.25 m.
  EXPECT_FALSE(choose_altitude(AltitudeSource::kAuto, 5.24, 5.0, dr).tracked);
  const AltitudeChoice wrong = choose_altitude(AltitudeSource::kAuto, 5.26, 5.0, dr);
  EXPECT_TRUE(wrong.tracked);
  EXPECT_TRUE(wrong.header_disagreed);
  EXPECT_EQ(wrong.altitude_m, 5.0);
  const AltitudeChoice zero = choose_altitude(AltitudeSource::kAuto, 0.0, 5.0, dr);
  EXPECT_TRUE(zero.tracked);
  EXPECT_FALSE(zero.header_disagreed);
  EXPECT_EQ(choose_altitude(AltitudeSource::kAuto, 5.0, std::nan(""), dr).altitude_m, 5.0);
  EXPECT_TRUE(std::isnan(choose_altitude(AltitudeSource::kHeader, 0.0, 5.0, dr).altitude_m));
  EXPECT_EQ(choose_altitude(AltitudeSource::kHeader, 9.0, 5.0, dr).altitude_m, 9.0);
  EXPECT_EQ(choose_altitude(AltitudeSource::kTrack, 9.0, 5.0, dr).altitude_m, 5.0);
  EXPECT_TRUE(
      std::isnan(choose_altitude(AltitudeSource::kTrack, 9.0, std::nan(""), dr).altitude_m));
  EXPECT_THROW(parse_altitude_source("both", "--altitude-source"), InputError);
  EXPECT_THROW(parse_gain_normalisation("beam", "--gain-normalisation"), InputError);
}

// A ramp g(r) = 1 + 3 r / R over a constant seabed: with one range bin per sample, each bin's
// geometric mean is g itself, so the normalised side is the constant exp(mean log of all
// counted samples) of both sides.
TEST(GainNormaliser, RangeModeFlattensAnAcrossTrackRamp) {
  const std::size_t n = 400;
  const double range_m = 40.0, dr = range_m / static_cast<double>(n), alt = 8.0;
  const auto ramp = [&](double scale) {
    std::vector<float> s(n);
    for (std::size_t j = 0; j < n; ++j) {
      const double r = (static_cast<double>(j) + 0.5) * dr;
      s[j] = static_cast<float>(scale * (1.0 + 3.0 * r / range_m));
    }
    return s;
  };
  GainNormaliser g(GainNormalisation::kRange, dr, 0.01, 10);
  for (int k = 0; k < 20; ++k) g.add_ping(ramp(10.0), ramp(40.0), range_m, alt);
  g.finish();
  // Expected level: mean of log over the counted samples (r > alt) of both sides.
  double sum = 0.0, count = 0.0;
  for (double scale : {10.0, 40.0}) {
    for (std::size_t j = 0; j < n; ++j) {
      const double r = (static_cast<double>(j) + 0.5) * dr;
      if (r <= alt) continue;
      sum += std::log(scale * (1.0 + 3.0 * r / range_m));
      count += 1.0;
    }
  }
  const double level = std::exp(sum / count);
  std::vector<float> p = ramp(10.0), s = ramp(40.0);
  const std::vector<float> p0 = p;
  g.apply(p, s, range_m, alt);
  for (std::size_t j = 0; j < n; ++j) {
    const double r = (static_cast<double>(j) + 0.5) * dr;
    if (r <= alt) {
      EXPECT_EQ(p[j], p0[j]) << "water column untouched";
      continue;
    }
    EXPECT_NEAR(p[j], level, 1e-4 * level) << "port sample " << j;
    EXPECT_NEAR(s[j], level, 1e-4 * level) << "starboard sample " << j;
  }
}

// Angle mode: g = 1 + 2 theta (theta the depression angle asin(alt / r)); within a bin of
// 0.5 degree g varies by at most a factor 1 + 2 x 0.00873 / 1 (bins without a sample are
// interpolated in log, nearly exact for this ramp), so the normalised samples lie within 2 % of
// one another where the ramp itself spans a factor of up to 3.5.
TEST(GainNormaliser, AngleModeFlattensAGrazingAngleRampAcrossAltitudes) {
  const std::size_t n = 800;
  const double range_m = 50.0, dr = range_m / static_cast<double>(n);
  const auto ping = [&](double alt) {
    std::vector<float> s(n);
    for (std::size_t j = 0; j < n; ++j) {
      const double r = (static_cast<double>(j) + 0.5) * dr;
      s[j] = r > alt ? static_cast<float>(100.0 * (1.0 + 2.0 * std::asin(alt / r))) : 1.0f;
    }
    return s;
  };
  // 50 pings give few samples per bin near nadir (the angle changes fast with range there):
  // every bin with a sample counts.
  GainNormaliser g(GainNormalisation::kAngle, 0.25, 0.5 * std::numbers::pi / 180.0, 1);
  for (int k = 0; k < 50; ++k) {
    const double alt = 5.0 + 0.2 * k;
    g.add_ping(ping(alt), ping(alt), range_m, alt);
  }
  g.finish();
  for (double alt : {6.0, 12.0}) {
    std::vector<float> p = ping(alt), s = ping(alt);
    g.apply(p, s, range_m, alt);
    float lo = 1e30f, hi = 0.0f;
    for (std::size_t j = 0; j < n; ++j) {
      const double r = (static_cast<double>(j) + 0.5) * dr;
      if (r <= alt) continue;
      lo = std::min({lo, p[j], s[j]});
      hi = std::max({hi, p[j], s[j]});
    }
    EXPECT_LT(hi / lo, 1.02f) << "altitude " << alt;
    // Before: the ramp spans 1 + pi (nadir) down to about 1.2.
  }
}

TEST(GainNormaliser, BinsByRunsAreTheBinsOfEachSample) {
  // bins_of_ping finds the angle bins by runs; each sample's bin by its definition,
  // floor(asin(altitude / r) / bin), must be the same everywhere, bin edges included.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::ptrdiff_t> bins;
  std::size_t checked = 0;
  for (int k = 0; k < 400; ++k) {
    const double bin_rad = (k % 4 == 0 ? 0.5 : 0.05 + 2.0 * u(rng)) * std::numbers::pi / 180.0;
    const GainNormaliser g(GainNormalisation::kAngle, 0.25, bin_rad, 1);
    const std::size_t n = 1 + static_cast<std::size_t>(u(rng) * 5000.0);
    const double range_m = 5.0 + 200.0 * u(rng);
    const double dr = range_m / static_cast<double>(n);
    // Altitudes at a bin centre of the range (the first seabed sample), and altitudes that
    // put a sample on a bin's edge (asin(alt / r) = b bin to round-off: either side may win).
    const double r_m = (std::floor(u(rng) * static_cast<double>(n)) + 0.5) * dr;
    double alt = 0.5 + 0.8 * range_m * u(rng);
    if (k % 3 == 0) alt = r_m;
    if (k % 3 == 1)
      alt = r_m * std::sin(std::floor(u(rng) * 0.5 * std::numbers::pi / bin_rad) * bin_rad);
    if (!(alt > 0.0)) alt = r_m;
    g.bins_of_ping(n, dr, alt, bins);
    ASSERT_EQ(bins.size(), n);
    for (std::size_t i = 0; i < n; ++i) {
      const double r = (static_cast<double>(i) + 0.5) * dr;
      const std::ptrdiff_t want =
          r > alt ? static_cast<std::ptrdiff_t>(std::asin(std::clamp(alt / r, 0.0, 1.0)) / bin_rad)
                  : -1;
      ASSERT_EQ(bins[i], want) << "sample " << i << " of " << n << ", altitude " << alt;
      ++checked;
    }
  }
  EXPECT_GT(checked, 500000u);
  // Range bins: floor(r / bin).
  const GainNormaliser g(GainNormalisation::kRange, 0.3, 0.01, 1);
  g.bins_of_ping(1000, 0.05, 7.0, bins);
  for (std::size_t i = 0; i < 1000; ++i) {
    const double r = (static_cast<double>(i) + 0.5) * 0.05;
    EXPECT_EQ(bins[i], r > 7.0 ? static_cast<std::ptrdiff_t>(r / 0.3) : -1);
  }
}

TEST(GainNormaliser, OffChangesNothing) {
  GainNormaliser g(GainNormalisation::kOff);
  std::vector<float> p{1.0f, 2.0f, 3.0f}, s{4.0f, 5.0f, 6.0f};
  g.add_ping(p, s, 3.0, 0.5);
  g.finish();
  g.apply(p, s, 3.0, 0.5);
  EXPECT_EQ(p, (std::vector<float>{1.0f, 2.0f, 3.0f}));
  EXPECT_EQ(s, (std::vector<float>{4.0f, 5.0f, 6.0f}));
}

}  // namespace
}  // namespace sonarsynth
