// SPDX-License-Identifier: MIT
// The realism measures (bench/realism_stats.hpp, docs/realism.md) on synthetic records with
// known answers: Rayleigh and exponential speckle, planted water column, transmit pulse, zeros,
// clipping, first-return steps and ramps, shadows and AR(1) along-track sequences.
#include "realism_stats.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

#include "error_test_util.hpp"
#include "realism_test_records.hpp"
#include "sonarsynth/error.hpp"

namespace rs = bench::realism;
using rs::Side;
using sonarsynth::test::expect_error;

using namespace realism_test;

TEST(RealismStats, RayleighAmplitudeContrastAndDbStd) {
  const auto pings = rayleigh_record(300, 1000.0, 11);
  for (Side side : {Side::kPort, Side::kStarboard}) {
    const rs::Options o;
    const auto fr = rs::first_returns(pings, side, o);
    const rs::Texture t = rs::seabed_texture(pings, side, fr, o);
    // The local mean over 5 x 31 samples includes the sample: contrast low by about 1/155.
    EXPECT_NEAR(t.contrast(), kRayleighContrast, 0.008);
    EXPECT_NEAR(t.db.stddev(), kRayleighDbStd, 0.03);
    EXPECT_NEAR(t.median_tile_contrast(), kRayleighContrast, 0.01);
    EXPECT_NEAR(t.median_tile_db_std(), kRayleighDbStd, 0.04);
    // Independent pings: no along-track correlation (the shared local mean biases it by ~-1/155).
    for (std::size_t b = 2; b < 9; ++b) EXPECT_NEAR(t.bands[b].correlation(), 0.0, 0.02) << b;
    // Every grazing class with samples sees the same speckle.
    for (std::size_t c = 0; c < t.grazing_ratio.size(); ++c) {
      if (t.grazing_ratio[c].n > 10000) {
        EXPECT_NEAR(t.grazing_ratio[c].stddev() / t.grazing_ratio[c].mean(), kRayleighContrast,
                    0.015)
            << c;
      }
    }
  }
  rs::Options wide;  // a local mean over many samples leaves the sample's own share negligible
  wide.box_pings = 21;
  wide.box_samples = 101;
  const auto fr = rs::first_returns(pings, Side::kPort, wide);
  const rs::Texture t = rs::seabed_texture(pings, Side::kPort, fr, wide);
  EXPECT_NEAR(t.contrast(), kRayleighContrast, 0.004);
  EXPECT_NEAR(t.db.stddev(), kRayleighDbStd, 0.02);
}

TEST(RealismStats, ExponentialIntensityContrastAndDbStd) {
  Draw d(12);
  const auto pings = make_pings(300, [&](std::size_t, std::size_t i, Side) {
    return i < kBottom ? kWater : static_cast<float>(d.exponential(1.0e4));
  });
  const rs::Options o;
  const auto fr = rs::first_returns(pings, Side::kStarboard, o);
  const rs::Texture t = rs::seabed_texture(pings, Side::kStarboard, fr, o);
  EXPECT_NEAR(t.contrast(), 1.0, 0.015);
  EXPECT_NEAR(t.db.stddev(), kExponentialDbStd, 0.06);
}

TEST(RealismStats, WaterColumnTransmitZerosAndClipping) {
  constexpr double kSigma = 1000.0;
  constexpr float kFullScale = 32767.0f;
  Draw d(13);
  // Transmit pulse at full scale in samples 0-3, water column kWater, Rayleigh seabed with, from
  // sample 200 on, an exact zero at every 50th sample and a clipped one at every 100th (+1).
  const auto pings = make_pings(400, [&](std::size_t, std::size_t i, Side) {
    if (i < 4) return kFullScale;
    if (i < kBottom) return kWater;
    const float v = static_cast<float>(d.rayleigh(kSigma));
    if (i >= 200 && i % 50 == 0) return 0.0f;
    if (i >= 200 && i % 100 == 1) return kFullScale;
    return v;
  });
  const rs::Report r = rs::measure(pings);
  EXPECT_EQ(r.max_value, kFullScale);
  // By the definitions: r0 = 10.05 m, the seabed is samples 121-899 (centres in [12.06, 90) m),
  // with 14 zeros (200 ... 850) and 7 clipped samples (201 ... 801); the near seabed is samples
  // 121-150 (centres in [12.06, 15.075) m), plain Rayleigh.
  constexpr double kSeabedSamples = 779.0;
  for (const rs::SideReport* s : {&r.port, &r.starboard, &r.pooled}) {
    const rs::Levels& l = s->levels;
    // Median of Rayleigh(sigma) = sigma sqrt(2 ln 2); the water column is kWater exactly.
    const double seabed_db = 20.0 * std::log10(kSigma * std::sqrt(2.0 * std::log(2.0)));
    EXPECT_NEAR(l.water.median_db(), 20.0 * std::log10(kWater), 0.01);
    EXPECT_NEAR(l.near.median_db(), seabed_db, 0.2);
    EXPECT_NEAR(l.water.median_db() - l.near.median_db(), 20.0 * std::log10(kWater) - seabed_db,
                0.2);
    EXPECT_NEAR(rs::quantile(l.ping_water_minus_near_db, 0.5),
                20.0 * std::log10(kWater) - seabed_db, 0.25);
    EXPECT_EQ(l.water_zeros, 0u);
    const auto seabed = static_cast<double>(l.seabed.count());
    EXPECT_NEAR(static_cast<double>(l.seabed_zeros) / seabed, 14.0 / kSeabedSamples, 2e-4);
    EXPECT_EQ(l.zeros * kSamples, l.samples * 16);  // 200 ... 950 in every ping
    // Dark (< 16): the zeros plus Rayleigh draws below 16: 1 - exp(-16^2 / (2 sigma^2)).
    const double dark =
        (14.0 + (kSeabedSamples - 21.0) * (1.0 - std::exp(-256.0 / (2.0 * kSigma * kSigma)))) /
        kSeabedSamples;
    EXPECT_NEAR(static_cast<double>(l.seabed_dark) / seabed, dark, 2e-4);
    EXPECT_NEAR(static_cast<double>(l.seabed_clipped) / seabed, 7.0 / kSeabedSamples, 2e-4);
    EXPECT_EQ(l.near_clipped, 0u);
    // The leading samples are the transmit pulse, all at full scale.
    EXPECT_EQ(l.lead_clipped, l.lead.count());
    EXPECT_NEAR(l.lead.median_db(), 20.0 * std::log10(kFullScale), 0.01);
  }
  // The transmit pulse is not taken for the first return.
  const auto fr = rs::first_returns(pings, Side::kPort, rs::Options{});
  std::size_t exact = 0;
  for (const rs::FirstReturn& f : fr) exact += f.found && f.index == kBottom && f.water_begin == 4;
  EXPECT_GE(exact, fr.size() * 95 / 100);
}

TEST(RealismStats, FirstReturnStepAtKnownSamplePerPing) {
  // A deterministic step: water kWater, seabed 1000 from sample 200 + k % 37 on.
  auto bottom = [](std::size_t k) { return 200 + k % 37; };
  const auto pings = make_pings(
      100, [&](std::size_t k, std::size_t i, Side) { return i < bottom(k) ? kWater : 1000.0f; },
      [&](std::size_t k) { return (static_cast<double>(bottom(k)) + 0.5) * kDr + 0.25; });
  const rs::Options o;
  for (Side side : {Side::kPort, Side::kStarboard}) {
    const auto fr = rs::first_returns(pings, side, o);
    for (std::size_t k = 0; k < pings.size(); ++k) {
      ASSERT_TRUE(fr[k].found) << k;
      EXPECT_EQ(fr[k].index, bottom(k)) << k;
      EXPECT_EQ(fr[k].water_begin, 0u);
      EXPECT_NEAR(fr[k].range_m, (static_cast<double>(bottom(k)) + 0.5) * kDr, 1e-12);
      EXPECT_NEAR(fr[k].seabed_db, 60.0, 1e-4);
    }
    const rs::FirstReturnStats s = rs::first_return_stats(pings, side, fr, o);
    EXPECT_EQ(s.found, pings.size());
    EXPECT_NEAR(rs::quantile(s.range_minus_altitude_m, 0.5), -0.25, 1e-9);
    EXPECT_NEAR(s.rise_m(12.0), 0.0, 1e-12);  // a step reaches the seabed level at once
  }
  // With Rayleigh speckle after the step the first sample can be dark; most pings stay exact.
  Draw d(14);
  const auto noisy = make_pings(300, [&](std::size_t k, std::size_t i, Side) {
    return i < bottom(k) ? kWater : static_cast<float>(d.rayleigh(1000.0));
  });
  const auto fr = rs::first_returns(noisy, Side::kStarboard, o);
  std::size_t exact = 0;
  for (std::size_t k = 0; k < fr.size(); ++k) exact += fr[k].found && fr[k].index == bottom(k);
  EXPECT_GE(exact, fr.size() * 95 / 100);
}

TEST(RealismStats, FirstReturnRiseDistances) {
  // From sample 400 the level ramps from -17.9 dB by 0.3 dB a sample to the seabed level, so it
  // reaches -12 dB 20 samples and -3 dB 50 samples after the first return.
  constexpr std::size_t kRise = 400;
  constexpr double kSeabed = 5000.0;
  const auto pings = make_pings(50, [&](std::size_t, std::size_t i, Side) {
    if (i < kRise) return static_cast<float>(kSeabed * 0.01);  // -40 dB
    const double db = std::min(0.0, -17.9 + 0.3 * static_cast<double>(i - kRise));
    return static_cast<float>(kSeabed * std::pow(10.0, db / 20.0));
  });
  rs::Options o;
  o.rise_span_m = 8.0;
  const auto fr = rs::first_returns(pings, Side::kPort, o);
  ASSERT_TRUE(fr[0].found);
  EXPECT_EQ(fr[0].index, kRise);
  const rs::FirstReturnStats s = rs::first_return_stats(pings, Side::kPort, fr, o);
  EXPECT_NEAR(s.rise_m(12.0), 20 * kDr, 1e-9);
  EXPECT_NEAR(s.rise_m(3.0), 50 * kDr, 1e-9);
  // In units of r0 = 40.05 m: 5.0 m is 12.48 % of r0, the first 0.5 % step at or beyond it 12.5 %.
  EXPECT_NEAR(s.rise_r0(3.0), 0.125, 1e-9);
}

TEST(RealismStats, ShadowLevelAgainstLitSeabedAndWaterColumn) {
  constexpr double kSigma = 1000.0, kShadowDb = -25.0;
  Draw d(15);
  // A shadow 25 dB below the seabed over pings 80-120 and samples 500-600 (50-60 m).
  auto in_shadow = [](std::size_t k, std::size_t i) {
    return k >= 80 && k <= 120 && i >= 500 && i <= 600;
  };
  const auto pings = make_pings(200, [&](std::size_t k, std::size_t i, Side side) {
    if (i < kBottom) return kWater;
    const bool shadow = side == Side::kStarboard && in_shadow(k, i);
    return static_cast<float>(
        d.rayleigh(shadow ? kSigma * std::pow(10.0, kShadowDb / 20.0) : kSigma));
  });
  const rs::Options o;
  const auto fr = rs::first_returns(pings, Side::kStarboard, o);
  const rs::Shadows s = rs::shadows(pings, Side::kStarboard, fr, o);
  const rs::Levels l = rs::levels(pings, Side::kStarboard, fr, rs::max_sample(pings), o);
  // The 3 x 9 smoothing box loses about a ping and a few samples at each edge.
  const double planted = 41.0 * 101.0;
  EXPECT_GT(static_cast<double>(s.shadow), 0.85 * planted);
  EXPECT_LT(static_cast<double>(s.shadow), 1.01 * planted);
  EXPECT_NEAR(s.below_lit.median_db(), kShadowDb, 0.6);
  const double shadow_db =
      20.0 * std::log10(kSigma * std::pow(10.0, kShadowDb / 20.0) * std::sqrt(2.0 * std::log(2.0)));
  EXPECT_NEAR(s.level.median_db() - l.water.median_db(), shadow_db - 20.0 * std::log10(kWater),
              0.6);
  // No shadow on the port side, whose seabed is plain speckle.
  const auto fp = rs::first_returns(pings, Side::kPort, o);
  const rs::Shadows none = rs::shadows(pings, Side::kPort, fp, o);
  EXPECT_LT(static_cast<double>(none.shadow), 1e-4 * static_cast<double>(none.seabed));
}

TEST(RealismStats, LagOneCorrelationOfAr1Sequences) {
  for (double rho : {0.5, 0.9}) {
    Draw d(16);
    // Every sample column is an AR(1) sequence along-track with coefficient rho.
    std::vector<double> state(kSamples);
    for (double& x : state) x = d.normal();
    std::vector<rs::Ping> pings = make_pings(400, [&](std::size_t k, std::size_t i, Side side) {
      if (side == Side::kPort && k > 0)
        state[i] = rho * state[i] + std::sqrt(1 - rho * rho) * d.normal();
      return i < kBottom ? kWater : static_cast<float>(1000.0 + 100.0 * state[i]);
    });
    rs::Options wide;  // the local mean spans most of one ping's seabed: a plain rescaling
    wide.box_pings = 1;
    wide.box_samples = 801;
    const auto fr = rs::first_returns(pings, Side::kPort, wide);
    const rs::Texture t = rs::seabed_texture(pings, Side::kPort, fr, wide);
    for (std::size_t b = 2; b < 9; ++b) {
      EXPECT_NEAR(t.bands[b].correlation(), rho, 0.01) << rho << " band " << b;
      EXPECT_NEAR(t.median_tile_lag1(b), rho, 0.03) << rho << " band " << b;
    }
    // The default 5 x 31 local mean shares samples with both pings of a pair: for these
    // sequences it lowers the correlation by about 0.01.
    const rs::Options o;
    const rs::Texture td = rs::seabed_texture(pings, Side::kPort, fr, o);
    EXPECT_NEAR(td.bands[5].correlation(), rho, 0.03) << rho;
  }
}

TEST(RealismStats, PingSpacingFromHeldNavigation) {
  // 0.1 m per ping, but each position is held for two pings (navigation at half the ping rate).
  auto pings = make_pings(100, [](std::size_t, std::size_t, Side) { return 1.0f; });
  for (std::size_t k = 0; k < pings.size(); ++k) {
    pings[k].x_m = 0.2 * static_cast<double>(k / 2) * std::cos(0.5);
    pings[k].y_m = 0.2 * static_cast<double>(k / 2) * std::sin(0.5);
    pings[k].position_valid = k != 0;  // the first ping has no position
  }
  EXPECT_NEAR(rs::median_ping_spacing_m(pings, 10), 0.1, 1e-9);
}

TEST(RealismStats, HistogramQuantilesAndZeros) {
  rs::LevelHistogram h;
  EXPECT_TRUE(std::isnan(h.median_db()));
  for (int i = 0; i < 3; ++i) h.add_value(0.0);
  for (double v : {10.0, 100.0, 1000.0, 10000.0}) h.add_value(v);
  EXPECT_EQ(h.count(), 7u);
  EXPECT_NEAR(h.median_db(), 20.0, 0.01);
  EXPECT_EQ(h.quantile_db(0.0), -std::numeric_limits<double>::infinity());
  EXPECT_NEAR(h.quantile_db(1.0), 80.0, 0.01);
  rs::LevelHistogram g;
  for (int i = 0; i < 10; ++i) g.add_value(1.0e5);
  h.merge(g);
  EXPECT_NEAR(h.median_db(), 100.0, 0.01);
}

TEST(RealismStats, LayoutAndOptionErrorsAreNamed) {
  auto pings = make_pings(3, [](std::size_t, std::size_t, Side) { return 1.0f; });
  pings[2].starboard.resize(10);
  expect_error([&] { rs::measure(pings); }, {"ping 2"}, "mixed layouts");
  EXPECT_THROW(rs::measure(std::vector<rs::Ping>{}), sonarsynth::InputError);
  pings[2].starboard.resize(kSamples);
  EXPECT_THROW(rs::seabed_texture(pings, Side::kPort, std::vector<rs::FirstReturn>(2), {}),
               sonarsynth::InputError);
  rs::Options o;
  o.box_samples = 30;
  expect_error([&] { o.validate(); }, {"box_samples = 30"}, "an even box");
}

TEST(RealismStats, ShadowFillCoefficientOfVariation) {
  // Rayleigh lit seabed (CV sqrt(4/pi - 1)) with two shadows on starboard whose values are
  // exponential (CV 1), 30 dB below the seabed.
  constexpr double kSigma = 1000.0;
  const double shadow_mean = kSigma * std::sqrt(kPi / 2.0) * std::pow(10.0, -30.0 / 20.0);
  auto in_shadow = [](std::size_t k, std::size_t i) {
    return (k >= 80 && k <= 120 && i >= 500 && i <= 600) ||
           (k >= 200 && k <= 240 && i >= 300 && i <= 400);
  };
  Draw d(23);
  const auto pings = make_pings(300, [&](std::size_t k, std::size_t i, Side side) {
    if (i < kBottom) return kWater;
    if (side == Side::kStarboard && in_shadow(k, i))
      return static_cast<float>(d.exponential(shadow_mean));
    return static_cast<float>(d.rayleigh(kSigma));
  });
  const rs::Options o;
  const auto fr = rs::first_returns(pings, Side::kStarboard, o);
  const rs::Shadows s = rs::shadows(pings, Side::kStarboard, fr, o);
  EXPECT_NEAR(s.cv_shadow(), 1.0, 0.05);
  EXPECT_NEAR(s.cv_lit(), kRayleighContrast, 0.01);
  ASSERT_EQ(s.region_cv.size(), 2u);
  for (double cv : s.region_cv) EXPECT_NEAR(cv, 1.0, 0.08);
}

TEST(RealismStats, ShadowEdgeWidthOfAKnownRamp) {
  // Every third ping has a shadow (value 10) from 15 m to t0, then a ramp linear in value over
  // 5 samples to the seabed's 1000: 10 + 990 u / 5 at t0 + u. Its 10-90 % width is 0.8 x 5
  // samples = 0.4 m wherever the edge is. The detection (one ping x 9 samples) ends at t0.
  for (std::size_t base : {180u, 500u}) {
    auto t0 = [&](std::size_t k) { return base + 5 * (k % 4); };
    const auto pings = make_pings(200, [&](std::size_t k, std::size_t i, Side) {
      if (i < kBottom) return kWater;
      if (k % 3 != 0 || i < 150) return 1000.0f;
      if (i <= t0(k)) return 10.0f;
      return static_cast<float>(10.0 + 990.0 * std::min(1.0, static_cast<double>(i - t0(k)) / 5.0));
    });
    rs::Options o;
    o.shadow_box_pings = 1;
    for (Side side : {Side::kPort, Side::kStarboard}) {
      const auto fr = rs::first_returns(pings, side, o);
      const rs::Shadows s = rs::shadows(pings, side, fr, o);
      // Edges at 18-19.5 m fall in the 15-25 m window; at 50-51.5 m all ranges are used.
      EXPECT_EQ(s.edge_in_window(), base == 180u) << base;
      EXPECT_EQ(s.edge_count(), 67u) << base;
      EXPECT_NEAR(s.edge_width_m(), 0.4, 1e-6) << base;
      const std::vector<double> p = s.edge_profile();
      ASSERT_EQ(p.size(), 15u);  // 0.5 m of shadow (5 samples) and 1 m of lit seabed (10)
      EXPECT_NEAR(p[s.edge_before], 10.0, 1e-3);
      EXPECT_NEAR(p[s.edge_before + 1], 208.0, 1e-3);
    }
  }
}

TEST(RealismStats, RiseWidthOfLinearRamps) {
  // A ramp from 0 to 1 over samples 10 .. 30: 10 % at 12, 90 % at 28.
  std::vector<double> p(50);
  for (std::size_t i = 0; i < p.size(); ++i)
    p[i] = std::clamp((static_cast<double>(i) - 10.0) / 20.0, 0.0, 1.0);
  EXPECT_NEAR(rs::rise_width_10_90(p, 0.0, 1.0), 16.0, 1e-12);
  EXPECT_TRUE(std::isnan(rs::rise_width_10_90(p, 1.0, 0.0)));
}

TEST(RealismStats, WaterColumnGammaStatistics) {
  // Water column 10 + Gamma(2, 25) (sum of two exponentials): mean 60, std 25 sqrt 2, CV
  // 0.589, skewness sqrt 2. First return at sample 400 (r0 = 40.05 m): the window is samples
  // 20 .. 339 (centres below 0.85 r0 = 34.04 m). On starboard the water doubles from sample
  // 200 on: its last third is 6.02 dB above its first. One port sample is 3 (the lowest).
  constexpr std::size_t kBottomFar = 400;
  Draw d(24);
  const auto pings = make_pings(320, [&](std::size_t k, std::size_t i, Side side) {
    if (i >= kBottomFar) return static_cast<float>(d.rayleigh(8000.0));
    if (side == Side::kPort && k == 10 && i == 100) return 3.0f;
    const double w = 10.0 + d.exponential(25.0) + d.exponential(25.0);
    return static_cast<float>(side == Side::kStarboard && i >= 200 ? 2.0 * w : w);
  });
  const rs::Options o;
  const double cv = 25.0 * std::sqrt(2.0) / 60.0, skew = std::sqrt(2.0);
  const auto fp = rs::first_returns(pings, Side::kPort, o);
  const rs::Levels l = rs::levels(pings, Side::kPort, fp, rs::max_sample(pings), o);
  EXPECT_EQ(l.water_block_cv.size(), 5u);
  EXPECT_NEAR(rs::quantile(l.water_block_cv, 0.5), cv, 0.01);
  EXPECT_NEAR(rs::quantile(l.water_ping_cv, 0.5), cv, 0.015);
  EXPECT_LT(rs::quantile(l.water_ping_cv, 0.25), cv);
  EXPECT_GT(rs::quantile(l.water_ping_cv, 0.75), cv);
  EXPECT_NEAR(l.water_stats.n, 320.0 * 320.0, 320.0 * 3.0);  // a few pings may miss r0
  EXPECT_NEAR(l.water_stats.cv(), cv, 0.005);
  EXPECT_NEAR(l.water_stats.skewness(), skew, 0.06);
  EXPECT_NEAR(rs::quantile(l.water_block_skewness, 0.5), skew, 0.12);
  EXPECT_EQ(l.water_min, 3.0);
  EXPECT_NEAR(l.water_trend_db(), 0.0, 0.15);
  const auto fs = rs::first_returns(pings, Side::kStarboard, o);
  const rs::Levels ls = rs::levels(pings, Side::kStarboard, fs, rs::max_sample(pings), o);
  EXPECT_NEAR(ls.water_trend_db(), 20.0 * std::log10(2.0), 0.15);
}

TEST(RealismStats, FirstReturnProfileFromR0AndFromAltitude) {
  // From sample 400 (r0 = 40.05 m) the level ramps from -17.9 dB by 0.3 dB a sample. The
  // sample nearest r0 + d is 400 + round(d / 0.1 m): offsets 0 0 1 1 2 5 9 for d = 0, 0.03,
  // 0.06, 0.09, 0.2, 0.5, 0.9 m. The header altitude 40.23 m is in sample 402; H + d falls in
  // samples 402 402 402 403 404 407 411.
  constexpr std::size_t kRise = 400;
  constexpr double kSeabed = 5000.0;
  const auto ramp = make_pings(
      50,
      [&](std::size_t, std::size_t i, Side) {
        if (i < kRise) return static_cast<float>(kSeabed * 0.01);
        const double db = std::min(0.0, -17.9 + 0.3 * static_cast<double>(i - kRise));
        return static_cast<float>(kSeabed * std::pow(10.0, db / 20.0));
      },
      [](std::size_t) { return 402.3 * kDr; });
  const rs::Options o;
  const auto fr = rs::first_returns(ramp, Side::kPort, o);
  const rs::FirstReturnStats s = rs::first_return_stats(ramp, Side::kPort, fr, o);
  const int from_r0[7] = {0, 0, 1, 1, 2, 5, 9}, from_h[7] = {2, 2, 2, 3, 4, 7, 11};
  ASSERT_EQ(s.profile_offsets_m.size(), 7u);
  for (std::size_t j = 0; j < 7; ++j) {
    EXPECT_NEAR(s.profile_db(j), -17.9 + 0.3 * from_r0[j], 1e-3) << j;
    EXPECT_NEAR(s.profile_db(j, true), -17.9 + 0.3 * from_h[j], 1e-3) << j;
  }
  EXPECT_NEAR(s.profile_max_drop_db(), 0.0, 1e-9);
  // A bright first return (3 samples), 8 dB lower for 5 samples, then the seabed: not monotone.
  const auto dip = make_pings(50, [&](std::size_t, std::size_t i, Side) {
    if (i < kRise) return static_cast<float>(kSeabed * 0.01);
    const bool low = i >= kRise + 3 && i < kRise + 8;
    return static_cast<float>(low ? kSeabed * std::pow(10.0, -8.0 / 20.0) : kSeabed);
  });
  const auto fd = rs::first_returns(dip, Side::kPort, o);
  const rs::FirstReturnStats sd = rs::first_return_stats(dip, Side::kPort, fd, o);
  EXPECT_NEAR(sd.profile_max_drop_db(), 8.0, 1e-3);
  EXPECT_TRUE(std::isnan(sd.profile_db(0, true)));  // no header altitude
}

TEST(RealismStats, FarRangeNearRangeClippingPercentilesAndAltitude) {
  // Water 20 (samples 0-99), seabed 1000 to 80 m and 100 beyond (-20 dB at [0.9, 0.97) R
  // against [1.4, 1.6) r0); in [r0, r0 + 2 m) = samples 100-119 every fourth sample is at full
  // scale (25 %). Levels of all samples: 10 % at 26.02 dB, 20 % at 40, 69.5 % at 60, 0.5 % at
  // 90.31. Header altitude 1 + 0.01 k m, none on ping 0.
  constexpr float kFullScale = 32767.0f;
  const auto pings = make_pings(
      201,
      [&](std::size_t, std::size_t i, Side) {
        if (i < kBottom) return kWater;
        if (i < 120 && i % 4 == 0) return kFullScale;
        return i < 800 ? 1000.0f : 100.0f;
      },
      [](std::size_t k) { return k == 0 ? 0.0 : 1.0 + 0.01 * static_cast<double>(k); });
  const rs::Report r = rs::measure(pings);
  for (const rs::SideReport* s : {&r.port, &r.starboard, &r.pooled}) {
    const rs::Levels& l = s->levels;
    EXPECT_NEAR(rs::quantile(l.far_minus_near_db, 0.5), -20.0, 1e-9);
    EXPECT_NEAR(rs::quantile(l.altitude_over_range, 0.5), 2.005 / kRangeM, 1e-12);
    EXPECT_EQ(l.first_metres * 5, l.first_metres_clipped * 20);
    EXPECT_NEAR(l.all.quantile_db(0.01), 20.0 * std::log10(kWater), 0.01);
    EXPECT_NEAR(l.all.quantile_db(0.2), 40.0, 0.01);
    EXPECT_NEAR(l.all.quantile_db(0.5), 60.0, 0.01);
    EXPECT_NEAR(l.all.quantile_db(0.99), 60.0, 0.01);
    EXPECT_NEAR(l.all.quantile_db(0.999), 20.0 * std::log10(kFullScale), 0.01);
  }
  EXPECT_EQ(r.pooled.levels.first_metres, 2u * 201u * 20u);
  EXPECT_NEAR(r.altitude_min_m, 1.01, 1e-12);
  EXPECT_NEAR(r.altitude_median_m, 2.005, 1e-12);
  EXPECT_NEAR(r.altitude_max_m, 3.0, 1e-12);
}
