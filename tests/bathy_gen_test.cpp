// SPDX-License-Identifier: MIT
#include "sonarsynth/bathy_gen.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth {
namespace {

BathyGenSpec base_spec(double width_m = 100.0, double height_m = 60.0, double cell_m = 0.5) {
  BathyGenSpec s;
  s.depth_m = 20.0;
  s.geometry = BathyGenSpec::centred_geometry(10.0, -5.0, width_m, height_m, cell_m);
  s.seed = 42;
  return s;
}

bool bit_identical(const HeightGrid& a, const HeightGrid& b) {
  return a.heights().size() == b.heights().size() &&
         std::memcmp(a.heights().data(), b.heights().data(), a.heights().size() * sizeof(float)) ==
             0;
}

TEST(BathyGen, CentredGeometryIsCentredAndNorthUp) {
  const GridGeometry g = BathyGenSpec::centred_geometry(10.0, -5.0, 100.0, 60.0, 0.5);
  EXPECT_EQ(g.cols, 200u);
  EXPECT_EQ(g.rows, 120u);
  EXPECT_DOUBLE_EQ(g.dx_m, 0.5);
  EXPECT_DOUBLE_EQ(g.dy_m, -0.5);
  EXPECT_NEAR(0.5 * (g.x_of_col(0) + g.x_of_col(199)), 10.0, 1e-12);
  EXPECT_NEAR(0.5 * (g.y_of_row(0) + g.y_of_row(119)), -5.0, 1e-12);
  EXPECT_GT(g.y_of_row(0), g.y_of_row(1));  // row 0 = north edge
}

TEST(BathyGen, FlatIsExactlyMinusDepth) {
  const HeightGrid g = generate_bathymetry(base_spec());
  ASSERT_EQ(g.heights().size(), 200u * 120u);
  for (float h : g.heights()) ASSERT_EQ(h, -20.0f);
}

TEST(BathyGen, PlaneSlopeIsExact) {
  BathyGenSpec s = base_spec();
  s.components.push_back(bathy::Plane{0.01, -0.02, 3.0, 4.0});
  const HeightGrid g = generate_bathymetry(s);
  const GridGeometry& geo = g.geometry();
  for (std::size_t r = 0; r < geo.rows; r += 7) {
    for (std::size_t c = 0; c < geo.cols; c += 5) {
      const double x = geo.x_of_col(static_cast<double>(c));
      const double y = geo.y_of_row(static_cast<double>(r));
      const double expect = -20.0 + 0.01 * (x - 3.0) - 0.02 * (y - 4.0);
      ASSERT_NEAR(g.node(c, r), expect, 1e-5) << c << "," << r;
    }
  }
}

TEST(BathyGen, PlaneFromDipDeepensTowardsAzimuth) {
  BathyGenSpec s = base_spec();
  // 2 degrees down towards grid east: constant along columns, -tan(2 deg) per metre along x.
  s.components.push_back(bathy::Plane::from_dip(rad_from_deg(2.0), rad_from_deg(90.0)));
  const HeightGrid g = generate_bathymetry(s);
  const double per_cell = -std::tan(rad_from_deg(2.0)) * 0.5;
  EXPECT_NEAR(g.node(101, 30) - g.node(100, 30), per_cell, 1e-5);
  EXPECT_NEAR(g.node(100, 31) - g.node(100, 30), 0.0, 1e-5);
  // Towards grid north (azimuth 0): heights fall as y grows, i.e. rise with the row index.
  BathyGenSpec n = base_spec();
  n.components.push_back(bathy::Plane::from_dip(rad_from_deg(2.0), 0.0));
  const HeightGrid gn = generate_bathymetry(n);
  EXPECT_NEAR(gn.node(100, 31) - gn.node(100, 30), -per_cell, 1e-5);
  EXPECT_THROW(bathy::Plane::from_dip(rad_from_deg(90.0), 0.0), InputError);
}

// Mean spacing of upward zero crossings (linearly interpolated) of z + depth along a row.
double mean_crossing_spacing(const HeightGrid& g, std::size_t row, double depth, int* count) {
  const GridGeometry& geo = g.geometry();
  double first = NAN, last = NAN;
  int n = 0;
  for (std::size_t c = 0; c + 1 < geo.cols; ++c) {
    const double a = g.node(c, row) + depth;
    const double b = g.node(c + 1, row) + depth;
    if (a < 0.0 && b >= 0.0) {
      const double x = geo.x_of_col(static_cast<double>(c) + a / (a - b));
      if (n == 0) first = x;
      last = x;
      ++n;
    }
  }
  *count = n;
  return n > 1 ? (last - first) / (n - 1) : NAN;
}

TEST(BathyGen, RippleWavelengthFromZeroCrossings) {
  for (const double asymmetry : {0.0, 0.6}) {
    BathyGenSpec s = base_spec(200.0, 20.0, 0.1);
    bathy::Ripples r;
    r.wavelength_m = 2.7;
    r.amplitude_m = 0.1;
    r.crest_azimuth_rad = 0.0;  // crests run grid north: the profile varies along x
    r.asymmetry = asymmetry;
    s.components.push_back(r);
    const HeightGrid g = generate_bathymetry(s);
    int n = 0;
    const double spacing = mean_crossing_spacing(g, 50, 20.0, &n);
    EXPECT_NEAR(n, 200.0 / 2.7, 1.0) << "asymmetry " << asymmetry;
    EXPECT_NEAR(spacing, 2.7, 0.002) << "asymmetry " << asymmetry;
    // Constant along the crests.
    EXPECT_NEAR(g.node(123, 10), g.node(123, 150), 1e-6);
    float lo = 1e9f, hi = -1e9f;
    for (float h : g.heights()) {
      lo = std::min(lo, h);
      hi = std::max(hi, h);
    }
    EXPECT_NEAR(hi, -19.9, 3e-3);
    EXPECT_NEAR(lo, -20.1, 3e-3);
  }
}

TEST(BathyGen, RippleCrestAzimuthRotatesThePattern) {
  BathyGenSpec s = base_spec(40.0, 40.0, 0.25);
  bathy::Ripples r;
  r.wavelength_m = 3.0;
  r.amplitude_m = 0.2;
  r.crest_azimuth_rad = rad_from_deg(90.0);  // crests run east: heights vary along y only
  s.components.push_back(r);
  const HeightGrid g = generate_bathymetry(s);
  float col_lo = 1e9f, col_hi = -1e9f;
  for (std::size_t row = 0; row < g.geometry().rows; ++row) {
    EXPECT_NEAR(g.node(3, row), g.node(150, row), 1e-6);
    col_lo = std::min(col_lo, g.node(3, row));
    col_hi = std::max(col_hi, g.node(3, row));
  }
  EXPECT_NEAR(col_hi - col_lo, 0.4, 0.02);  // crest sampled within 1/24 wavelength
}

bathy::Fbm test_fbm() {
  bathy::Fbm f;
  f.rms_m = 0.3;
  f.base_wavelength_m = 8.0;
  f.octaves = 5;
  f.persistence = 0.55;
  return f;
}

TEST(BathyGen, FbmRmsWithinTolerance) {
  BathyGenSpec s = base_spec(256.0, 256.0, 0.5);  // 32 x 32 coarse lattice cells
  s.components.push_back(test_fbm());
  const HeightGrid g = generate_bathymetry(s);
  double sum = 0.0, sum2 = 0.0;
  for (float h : g.heights()) {
    const double z = h + 20.0;
    sum += z;
    sum2 += z * z;
  }
  const double n = static_cast<double>(g.heights().size());
  const double mean = sum / n;
  const double rms = std::sqrt(sum2 / n);
  EXPECT_NEAR(rms, 0.3, 0.3 * 0.12);
  EXPECT_NEAR(mean, 0.0, 0.05);
}

TEST(BathyGen, FbmDeterministicPerSeedAndThreadCount) {
  BathyGenSpec s = base_spec(60.0, 50.0, 0.25);
  s.components.push_back(test_fbm());
  s.components.push_back(bathy::Seamount{5.0, 5.0, 3.0, 8.0});
  s.num_threads = 1;
  const HeightGrid one = generate_bathymetry(s);
  const HeightGrid again = generate_bathymetry(s);
  EXPECT_TRUE(bit_identical(one, again));
  for (unsigned t : {2u, 3u, 7u}) {
    s.num_threads = t;
    EXPECT_TRUE(bit_identical(one, generate_bathymetry(s))) << t << " threads";
  }
  s.seed = 43;
  const HeightGrid other = generate_bathymetry(s);
  EXPECT_FALSE(bit_identical(one, other));
  std::size_t differing = 0;
  for (std::size_t i = 0; i < one.heights().size(); ++i) {
    differing += one.heights()[i] != other.heights()[i];
  }
  EXPECT_GT(differing, one.heights().size() * 9 / 10);
}

TEST(BathyGen, FbmNodesEqualThePointDefinition) {
  // The row evaluator (lattice hashes per cell, not per node) against Fbm::height_m, which
  // evaluates gradient_noise point by point: equal to the bit at every node, on a grid finer
  // than the finest octave's lattice (cells reused) and one coarser (cells skipped), across the
  // origin (negative lattice indices).
  const bathy::Fbm f = test_fbm();
  for (const double cell_m : {0.1, 0.75}) {
    BathyGenSpec s = base_spec();
    s.geometry = BathyGenSpec::centred_geometry(0.3, -0.2, 40.0, 30.0, cell_m);
    s.components.push_back(f);
    const GridGeometry& g = s.geometry;
    HeightGrid grid(g, std::vector<float>(g.size(), 0.0f));
    add_bathymetry_components(s, grid);
    std::size_t checked = 0;
    for (std::size_t r = 0; r < g.rows; ++r) {
      const double y = g.y_of_row(static_cast<double>(r));
      for (std::size_t c = 0; c < g.cols; ++c) {
        const double x = g.x0_m + static_cast<double>(c) * g.dx_m;
        ASSERT_EQ(grid.node(c, r), static_cast<float>(f.height_m(x, y, s.seed)))
            << "cell " << cell_m << " node " << c << "," << r;
        ++checked;
      }
    }
    EXPECT_EQ(checked, g.size());
  }
}

TEST(BathyGen, ValuesDependOnPositionOnly) {
  // A grid shifted by whole cells shares nodes with the first: same heights there.
  BathyGenSpec a = base_spec(40.0, 30.0, 0.5);
  a.components.push_back(test_fbm());
  bathy::Ripples r;
  r.crest_azimuth_rad = 0.3;
  r.asymmetry = 0.4;
  a.components.push_back(r);
  BathyGenSpec b = a;
  b.geometry.x0_m += 7 * 0.5;
  b.geometry.y0_m -= 4 * 0.5;
  const HeightGrid ga = generate_bathymetry(a);
  const HeightGrid gb = generate_bathymetry(b);
  for (std::size_t r0 = 0; r0 + 4 < 60; r0 += 3) {
    for (std::size_t c = 0; c + 7 < 80; c += 3) {
      ASSERT_EQ(gb.node(c, r0), ga.node(c + 7, r0 + 4)) << c << "," << r0;
    }
  }
}

TEST(BathyGen, SeamountPeakHeightAndPosition) {
  BathyGenSpec s = base_spec(100.0, 60.0, 0.5);
  // Centre on a node: x0 = 10 - 49.75 = -39.75, so x = 3.25 is column 86.
  s.components.push_back(bathy::Seamount{3.25, -2.25, 5.0, 10.0});
  const HeightGrid g = generate_bathymetry(s);
  std::size_t best = 0;
  for (std::size_t i = 1; i < g.heights().size(); ++i) {
    if (g.heights()[i] > g.heights()[best]) best = i;
  }
  const GridGeometry& geo = g.geometry();
  EXPECT_NEAR(geo.x_of_col(static_cast<double>(best % geo.cols)), 3.25, 1e-9);
  EXPECT_NEAR(geo.y_of_row(static_cast<double>(best / geo.cols)), -2.25, 1e-9);
  EXPECT_NEAR(g.heights()[best], -15.0, 1e-5);
  // One radius (sigma) away: 5 exp(-1/2) above the base.
  EXPECT_NEAR(g.height_m(3.25 + 10.0, -2.25), -20.0 + 5.0 * std::exp(-0.5), 1e-5);
}

TEST(BathyGen, ScarpStepHeightAndSide) {
  BathyGenSpec s = base_spec(100.0, 60.0, 0.5);
  // Strike grid north through x = 10: the right side (east) is 4 m higher.
  s.components.push_back(bathy::Scarp{10.0, 0.0, 0.0, 4.0, 2.0});
  const HeightGrid g = generate_bathymetry(s);
  EXPECT_NEAR(g.height_m(55.0, 0.0), -18.0, 1e-5);
  EXPECT_NEAR(g.height_m(-35.0, 0.0), -22.0, 1e-5);
  EXPECT_NEAR(g.height_m(10.0, 0.0), -20.0, 1e-5);
  // Column 101 is at x = 10.75: d = 0.75 m.
  EXPECT_NEAR(g.node(101, 7), -20.0 + 2.0 * std::tanh(0.75), 1e-5);
}

TEST(BathyGen, GradientNoiseIsZeroOnLatticeAndBounded) {
  EXPECT_EQ(gradient_noise(3.0, -7.0, 1, 0), 0.0);
  double max_abs = 0.0;
  for (int i = 0; i < 2000; ++i) {
    max_abs = std::max(max_abs, std::abs(gradient_noise(0.37 * i, 0.61 * i, 9, 2)));
  }
  EXPECT_LE(max_abs, 1.0);
  EXPECT_GT(max_abs, 0.2);
}

template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

TEST(BathyGen, ValidationNamesTheViolatedConstraint) {
  BathyGenSpec s = base_spec();
  s.depth_m = 0.0;
  EXPECT_NE(error_of([&] { generate_bathymetry(s); }).find("depth_m = 0"), std::string::npos);
  s = base_spec();
  bathy::Ripples r;
  r.wavelength_m = -1.0;
  s.components.push_back(r);
  EXPECT_NE(error_of([&] { s.validate(); }).find("wavelength_m > 0"), std::string::npos);
  s = base_spec();
  bathy::Fbm f;
  f.octaves = 0;
  s.components.push_back(f);
  EXPECT_NE(error_of([&] { s.validate(); }).find("octaves = 0"), std::string::npos);
  EXPECT_NE(error_of([] { BathyGenSpec::centred_geometry(0, 0, 10, 10, 0.0); }).find("cell_m = 0"),
            std::string::npos);
  EXPECT_NE(error_of([] { BathyGenSpec::centred_geometry(0, 0, 10, 10, -2.0); }).find("cell_m > 0"),
            std::string::npos);
  EXPECT_THROW(BathyGenSpec::centred_geometry(0, 0, 1, 10, 1.0), InputError);  // 1 column
}

TEST(BathyGen, ValuesBeyondAnyOceanOrFinerThanTheGridAreRefused) {
  BathyGenSpec s = base_spec();  // 0.5 m cells
  s.depth_m = 1e9;
  EXPECT_NE(error_of([&] {
              s.validate();
            }).find("depth_m = 1000000000. Violated constraint: 0 < depth_m <= 11000"),
            std::string::npos);
  s.depth_m = 11000.0;
  EXPECT_NO_THROW(s.validate());
  s = base_spec();
  s.components.push_back(bathy::Seamount{0.0, 0.0, 1e9, 5.0});
  EXPECT_NE(error_of([&] { s.validate(); }).find("seamount height_m = 1000000000. Violated"),
            std::string::npos);
  s = base_spec();
  bathy::Ripples r;
  r.wavelength_m = 0.99;  // under two 0.5 m cells: would alias into noise
  s.components.push_back(r);
  EXPECT_NE(error_of([&] { s.validate(); }).find("wavelength_m >= 2 cells (1 m)"),
            std::string::npos);
  std::get<bathy::Ripples>(s.components[0]).wavelength_m = 1.0;
  EXPECT_NO_THROW(s.validate());
}

}  // namespace
}  // namespace sonarsynth
