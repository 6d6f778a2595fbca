// SPDX-License-Identifier: MIT
// The realism measure 7 (bench/realism_texture.cpp, docs/realism.md): across-track lag-1
// correlation and spectrum quarters of white speckle and of MA(1) and AR(1) sequences against
// their expected periodograms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

#include "realism_stats.hpp"
#include "realism_test_records.hpp"
#include "sonarsynth/error.hpp"

namespace rs = bench::realism;
using rs::Side;
using namespace realism_test;

namespace {

/// Expected periodogram of N samples of a stationary sequence with autocovariance gamma(m), at
/// bin f (f = 1 .. N/2): sum over |m| < N of (N - |m|) gamma(m) cos(2 pi f m / N). The mean
/// removed from each row does not change these bins.
std::vector<double> expected_periodogram(std::size_t n,
                                         const std::function<double(double)>& gamma) {
  std::vector<double> p(n / 2 + 1, 0.0);
  const auto nd = static_cast<double>(n);
  for (std::size_t f = 1; f <= n / 2; ++f) {
    double s = nd * gamma(0.0);
    for (std::size_t m = 1; m < n; ++m) {
      const auto md = static_cast<double>(m);
      s += 2.0 * (nd - md) * gamma(md) * std::cos(2.0 * kPi * static_cast<double>(f) * md / nd);
    }
    p[f] = s;
  }
  return p;
}

/// Mean of bins of quarter q over the mean of bins 1 .. N/2.
double expected_quarter(const std::vector<double>& p, std::size_t q) {
  const std::size_t half = p.size() - 1, quarter = half / 4;
  double all = 0.0, part = 0.0;
  for (std::size_t f = 1; f <= half; ++f) {
    all += p[f];
    if (f > q * quarter && f <= (q + 1) * quarter) part += p[f];
  }
  return (part / static_cast<double>(quarter)) / (all / static_cast<double>(half));
}

}  // namespace

TEST(RealismStats, AcrossTrackLagOneAndSpectrumOfWhiteSpeckle) {
  // iid Rayleigh speckle: no correlation between neighbouring samples and a flat spectrum.
  const auto pings = rayleigh_record(300, 1000.0, 21);
  const rs::Options o;
  for (Side side : {Side::kPort, Side::kStarboard}) {
    const auto fr = rs::first_returns(pings, side, o);
    const rs::Texture t = rs::seabed_texture(pings, side, fr, o);
    for (std::size_t p = 0; p < 3; ++p) {
      // Five tiles of 64 pings (the last of 44) at each place.
      EXPECT_EQ(t.tile_across_lag1(p).size(), 5u) << p;
      // The shared 31-sample local mean biases it by about -1/31.
      EXPECT_NEAR(t.median_tile_across_lag1(p), 0.0, 0.04) << p;
    }
    EXPECT_EQ(t.spectrum_rows(), 3u * 300u);
    for (std::size_t q = 0; q < 4; ++q) {
      EXPECT_NEAR(t.spectrum_quarter(q), 1.0, 0.05) << q;
      EXPECT_NEAR(t.median_tile_spectrum_quarter(q), 1.0, 0.08) << q;
    }
  }
}

TEST(RealismStats, AcrossTrackLagOneAndSpectrumOfMa1AndAr1Sequences) {
  // Along each ping's seabed a moving average x_i = e_i + e_(i-1) (lag-1 correlation 1/2,
  // autocovariance 2, 1, 0 ...) or an AR(1) sequence x_i = rho x_(i-1) + sqrt(1 - rho^2) e_i
  // (lag-1 rho, autocovariance rho^|m|); values 1000 + 100 x.
  constexpr double kRho = 0.6;
  for (bool ar : {false, true}) {
    Draw d(22);
    double prev_e[2] = {0.0, 0.0}, x[2] = {0.0, 0.0};  // per side: samples come interleaved
    const auto pings = make_pings(300, [&](std::size_t, std::size_t i, Side side) {
      if (i < kBottom) return kWater;
      const std::size_t c = side == Side::kPort ? 0 : 1;
      const double e = d.normal();
      if (ar) {
        x[c] = i == kBottom ? e : kRho * x[c] + std::sqrt(1.0 - kRho * kRho) * e;
      } else {
        x[c] = (i == kBottom ? d.normal() : prev_e[c]) + e;
        prev_e[c] = e;
      }
      return static_cast<float>(1000.0 + 100.0 * x[c]);
    });
    rs::Options wide;  // a local mean over most of the ping's seabed: a plain rescaling
    wide.box_pings = 1;
    wide.box_samples = 801;
    const double lag1 = ar ? kRho : 0.5;
    const std::vector<double> truth = expected_periodogram(wide.across_tile_samples, [&](double m) {
      if (ar) return std::pow(kRho, m);
      return m == 0.0 ? 2.0 : m == 1.0 ? 1.0 : 0.0;
    });
    for (Side side : {Side::kPort, Side::kStarboard}) {
      const auto fr = rs::first_returns(pings, side, wide);
      const rs::Texture t = rs::seabed_texture(pings, side, fr, wide);
      for (std::size_t p = 0; p < 3; ++p) {
        EXPECT_NEAR(t.median_tile_across_lag1(p), lag1, 0.03) << ar << " place " << p;
        EXPECT_NEAR(t.across[p].correlation(), lag1, 0.015) << ar << " place " << p;
      }
      for (std::size_t q = 0; q < 4; ++q)
        EXPECT_NEAR(t.spectrum_quarter(q), expected_quarter(truth, q), 0.04) << ar << " q " << q;
    }
    // Low-pass: the quarters fall. MA(1) (continuous form): 1 + (sin b - sin a) / (b - a).
    if (!ar) {
      const double a[5] = {0.0, kPi / 4, kPi / 2, 3 * kPi / 4, kPi};
      for (std::size_t q = 0; q < 4; ++q)
        EXPECT_NEAR(expected_quarter(truth, q),
                    1.0 + (std::sin(a[q + 1]) - std::sin(a[q])) / (kPi / 4), 0.03)
            << q;
    }
    // Pooled: each block's tiles of both sides merged, one tile per block and place.
    const rs::Report r = rs::measure(pings, wide);
    EXPECT_EQ(r.pooled.texture.tile_across_lag1(0).size(), 5u);
    EXPECT_NEAR(r.pooled.texture.median_tile_across_lag1(1), lag1, 0.03);
  }
}
