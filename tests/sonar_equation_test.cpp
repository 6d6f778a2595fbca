// SPDX-License-Identifier: MIT
// Absorption, beam patterns, TVG / quantisation and colormap against published values and
// closed forms (docs/physics.md §1.2, §1.3, §3.9).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sonarsynth/absorption.hpp"
#include "sonarsynth/beam_pattern.hpp"
#include "sonarsynth/colormap.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/render_side.hpp"
#include "sonarsynth/tvg.hpp"

namespace sonarsynth {
namespace {

constexpr double kPiT = 3.14159265358979323846;
double deg(double d) {
  return d * kPiT / 180.0;
}

TEST(Absorption, FrancoisGarrisonMatchesReferenceTable) {
  // docs/physics.md §1.2 table (S = 35, pH = 8, z = 20 m), dB/km, within 0.2 dB/km.
  const Seawater w10{10.0, 35.0, 20.0, 8.0};
  EXPECT_NEAR(francois_garrison_db_per_m(100e3, w10) * 1e3, 33.5, 0.2);
  EXPECT_NEAR(francois_garrison_db_per_m(400e3, w10) * 1e3, 95.9, 0.2);
  EXPECT_NEAR(francois_garrison_db_per_m(900e3, w10) * 1e3, 299.1, 0.2);
  const Seawater w4{4.0, 35.0, 20.0, 8.0}, w20{20.0, 35.0, 20.0, 8.0};
  EXPECT_NEAR(francois_garrison_db_per_m(455e3, w4) * 1e3, 113.2, 0.2);
  EXPECT_NEAR(francois_garrison_db_per_m(200e3, w20) * 1e3, 76.9, 0.2);
  // Check values 23.4 and 33.6 dB/km at 100 kHz, T = 0 and 10 C, S = 35 (surface).
  EXPECT_NEAR(francois_garrison_db_per_m(100e3, Seawater{0.0, 35.0, 0.0, 8.0}) * 1e3, 23.4, 0.1);
  EXPECT_NEAR(francois_garrison_db_per_m(100e3, Seawater{10.0, 35.0, 0.0, 8.0}) * 1e3, 33.6, 0.1);
  EXPECT_THROW(francois_garrison_db_per_m(-1.0, w10), InputError);
  EXPECT_THROW(francois_garrison_db_per_m(100e3, Seawater{50.0, 35.0, 0.0, 8.0}), InputError);
}

TEST(BeamPattern, AnalyticShapes) {
  VerticalBeamPattern g;
  g.shape = VerticalBeamShape::gaussian;
  g.width_3db_rad = deg(50);
  EXPECT_DOUBLE_EQ(g.one_way(0.0), 1.0);
  EXPECT_NEAR(g.one_way(deg(25)), 0.5, 1e-12);  // -3 dB at half the full width
  EXPECT_NEAR(g.one_way(-deg(25)), 0.5, 1e-12);
  EXPECT_NEAR(g.two_way(deg(25)), 0.25, 1e-12);

  VerticalBeamPattern s;
  s.shape = VerticalBeamShape::paper_sine_pair;
  s.upper_half_width_rad = deg(30);
  s.lower_half_width_rad = deg(20);
  EXPECT_DOUBLE_EQ(s.one_way(0.0), 1.0);
  EXPECT_NEAR(s.one_way(-deg(15)), std::cos(kPiT / 4), 1e-12);  // half-power at -w_up/2
  EXPECT_NEAR(s.one_way(deg(10)), std::cos(kPiT / 4), 1e-12);   // and at +w_down/2
  EXPECT_EQ(s.one_way(-deg(30.001)), 0.0);
  EXPECT_EQ(s.one_way(deg(20.001)), 0.0);

  VerticalBeamPattern c;
  c.shape = VerticalBeamShape::sinc;
  c.height_over_wavelength = 2.5;
  EXPECT_DOUBLE_EQ(c.one_way(0.0), 1.0);
  EXPECT_NEAR(c.one_way(std::asin(1.0 / 2.5)), 0.0, 1e-15);  // first null: sin = lambda / W
  const double x = kPiT * 2.5 * std::sin(0.1);
  EXPECT_NEAR(c.one_way(0.1), std::pow(std::sin(x) / x, 2), 1e-14);
}

TEST(BeamPattern, TableInterpolatesGainInDb) {
  VerticalBeamPattern t;
  t.shape = VerticalBeamShape::table;
  t.table_off_axis_rad = {deg(-40), deg(0), deg(20)};
  t.table_gain_db = {-20.0, 0.0, -10.0};
  t.validate();
  EXPECT_NEAR(t.one_way(0.0), 1.0, 1e-15);
  EXPECT_NEAR(t.one_way(deg(-20)), std::pow(10.0, -1.0), 1e-12);  // -10 dB halfway
  EXPECT_NEAR(t.one_way(deg(10)), std::pow(10.0, -0.5), 1e-12);   // -5 dB
  EXPECT_NEAR(t.one_way(deg(-60)), std::pow(10.0, -2.0), 1e-12);  // held end value
  t.table_off_axis_rad = {0.1, 0.1};
  t.table_gain_db = {0.0, 0.0};
  EXPECT_THROW(t.validate(), InputError);
  VerticalBeamPattern bad;
  bad.shape = VerticalBeamShape::gaussian;
  bad.width_3db_rad = 0.0;
  EXPECT_THROW(bad.validate(), InputError);
}

TEST(BeamPattern, EffectiveAlongTrackWidthOfLineArray) {
  // L >> lambda: integral of sinc^4 = 2 pi / 3 gives beta_eff -> 2 lambda / (3 L).
  const double lambda = 1500.0 / 400e3, length = 0.5;
  EXPECT_NEAR(beta_eff_uniform_line_array_rad(length, lambda), 2.0 * lambda / (3.0 * length),
              1e-4 * 2.0 * lambda / (3.0 * length));
  // Short array: independent composite Simpson over psi in [-pi/2, pi/2].
  const double l2 = 3.0 * lambda;
  const int n = 200000;
  const double h = kPiT / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double psi = -kPiT / 2 + i * h;
    const double x = kPiT * l2 / lambda * std::sin(psi);
    const double d = x == 0.0 ? 1.0 : std::sin(x) / x;
    sum += (i == 0 || i == n ? 1.0 : (i % 2 ? 4.0 : 2.0)) * d * d * d * d;
  }
  EXPECT_NEAR(beta_eff_uniform_line_array_rad(l2, lambda), sum * h / 3.0, 1e-9);
  EXPECT_THROW(beta_eff_uniform_line_array_rad(0.0, lambda), InputError);
}

TEST(Tvg, RoundTripAndGainValues) {
  Tvg tvg;
  tvg.absorption_db_per_m = 0.1;
  tvg.constant_db = -12.0;
  EXPECT_NEAR(tvg.gain_db(100.0), 60.0 + 20.0 - 12.0, 1e-12);
  std::vector<double> v(3000);
  for (std::size_t i = 0; i < v.size(); ++i)
    v[i] = 1e-9 * (1.0 + std::sin(0.01 * static_cast<double>(i)));
  const std::vector<double> orig = v;
  apply_tvg(tvg, 0.025, 0.05, v);
  remove_tvg(tvg, 0.025, 0.05, v);
  for (std::size_t i = 0; i < v.size(); ++i) ASSERT_NEAR(v[i], orig[i], 1e-14 * orig[i]);
  tvg.law = TvgLaw::none;
  EXPECT_EQ(tvg.gain_db(50.0), -12.0);
  tvg.min_range_m = 0.0;
  EXPECT_THROW(tvg.validate(), InputError);
}

TEST(Tvg, FlatBottomLevelAfterTvgIsGeometric) {
  // §3.9: with absorption and TVG 30 log r + 2 alpha r, the flat-bottom level per metre of range
  // is 10 log10(mu beta H^2 / (r y)) (beam pattern off).
  const double h = 10.01, dr = 0.01, alpha = 0.1, mu = 0.01, beta = 0.02;
  SideParams p;
  p.sample_spacing_m = dr;
  p.samples = 10000;
  p.beta_eff_rad = beta;
  p.vertical_beam.shape = VerticalBeamShape::uniform;
  p.materials[0].lambert_mu = mu;
  p.absorption_db_per_m = alpha;
  BeamProfile prof;
  prof.sensor_z_m = h;
  for (int i = 0; i <= 500; ++i) prof.add_node(0.25 * i, 0.0);
  SideEcho e;
  render_side(prof, p, e);
  std::vector<double> per_metre = e.intensity;
  for (double& x : per_metre) x /= dr;
  Tvg tvg;
  tvg.absorption_db_per_m = alpha;
  apply_tvg(tvg, 0.5 * dr, dr, per_metre);  // bin centres
  for (double r = 15.0; r < 95.0; r += 5.0) {
    const auto i = static_cast<std::size_t>(r / dr);
    const double rc = (static_cast<double>(i) + 0.5) * dr;
    const double y = std::sqrt(rc * rc - h * h);
    EXPECT_NEAR(10.0 * std::log10(per_metre[i]), 10.0 * std::log10(mu * beta * h * h / (rc * y)),
                0.001)
        << r;
  }
}

TEST(Quantizer, RoundTripWithinHalfStepAndClipsCounted) {
  const Quantizer q{60.0, 32767.0, true};
  std::vector<double> v = {0.0, 1e-6, 0.0123456, 0.04, 0.05, -1.0};
  std::size_t clipped = 99;
  const std::vector<float> s = quantize(v, q, &clipped);
  EXPECT_EQ(clipped, 2u);  // 0.04e6 and 0.05e6 exceed 32767
  EXPECT_EQ(s[3], 32767.0f);
  EXPECT_EQ(s[5], 0.0f);
  const std::vector<double> back = dequantize(s, q);
  EXPECT_NEAR(back[2], v[2], 0.5e-6);
  EXPECT_NEAR(back[1], v[1], 0.5e-6);
  const Quantizer f{0.0, 1e30, false};
  const std::vector<double> g = dequantize(quantize(v, f), f);
  EXPECT_NEAR(g[2], v[2], 1e-7 * v[2]);  // float32 precision
  EXPECT_THROW(quantize(v, Quantizer{0.0, 0.0, true}), InputError);
}

double luminance(const Rgb8& c) {
  return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

// The founding paper's eq. (3), written out here from the paper's text (docs/physics.md §1.9):
// channels in [0, 1] of a grey level I in [0, 1].
struct Rgb01 {
  double r, g, b;
};
Rgb01 paper_eq3(double i) {
  if (i < 0.8) return {1.25 * i, 0.7812 * i, 0.4975 * i};
  return {1.0, 1.883 * i - 0.883, -1.99 * i + 1.99};
}

TEST(Colormap, BlackBrownYellowIsPaperEquationThree) {
  for (const double i : {0.0, 0.4, 0.8, 0.9, 1.0, 0.1, 0.6, 0.79, 0.95}) {
    const Rgb01 want = paper_eq3(i);
    const Rgb8 got = colormap(Colormap::black_brown_yellow, i);
    EXPECT_NEAR(got.r, 255.0 * want.r, 1.0) << "I = " << i;
    EXPECT_NEAR(got.g, 255.0 * want.g, 1.0) << "I = " << i;
    EXPECT_NEAR(got.b, 255.0 * want.b, 1.0) << "I = " << i;
  }
  // The paper's named colours: black, brown (1, 0.625, 0.398) at 0.8, yellow.
  EXPECT_EQ(colormap(Colormap::black_brown_yellow, 0.0), (Rgb8{0, 0, 0}));
  EXPECT_EQ(colormap(Colormap::black_brown_yellow, 0.8), (Rgb8{255, 159, 101}));
  EXPECT_EQ(colormap(Colormap::black_brown_yellow, 1.0), (Rgb8{255, 255, 0}));
  // Blue is not zero below 0.8 (the earlier reading had no blue at all).
  EXPECT_EQ(colormap(Colormap::black_brown_yellow, 0.4).b, 51);
  // Clamped outside [0, 1]; NaN is black.
  EXPECT_EQ(colormap(Colormap::black_brown_yellow, 2.0), (Rgb8{255, 255, 0}));
  EXPECT_EQ(colormap(Colormap::black_brown_yellow, -1.0), (Rgb8{0, 0, 0}));
  EXPECT_EQ(colormap(Colormap::black_brown_yellow, std::nan("")), (Rgb8{0, 0, 0}));
  EXPECT_EQ(colormap(Colormap::grey, 0.5), (Rgb8{128, 128, 128}));
  EXPECT_EQ(colormap(Colormap::grey, std::nan("")), (Rgb8{0, 0, 0}));
}

TEST(Colormap, LuminanceRisesWithTheGreyLevel) {
  // Rec. 709 luminance of eq. (3) rises on both branches; after rounding to 8 bits a step may
  // lose at most one level of blue (weight 0.0722) where B falls above 0.8.
  for (const Colormap m : {Colormap::grey, Colormap::black_brown_yellow}) {
    double prev = -1.0;
    for (int i = 0; i <= 1000; ++i) {
      const double l = luminance(colormap(m, i / 1000.0));
      EXPECT_GE(l, prev - 0.0722 - 1e-12) << i;
      prev = l;
    }
    EXPECT_GT(luminance(colormap(m, 1.0)), luminance(colormap(m, 0.8)));
    EXPECT_GT(luminance(colormap(m, 0.8)), luminance(colormap(m, 0.4)));
  }
}

}  // namespace
}  // namespace sonarsynth
