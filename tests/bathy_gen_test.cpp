// SPDX-License-Identifier: MIT
#include "sonarsynth/bathy_gen.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "error_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth {
namespace {

using test::error_of;

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
    r.bandwidth = 0.0;  // the pure sinusoid
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
  r.bandwidth = 0.0;
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

TEST(BathyGen, PureRipplesReproduceTheSinusoidExactly) {
  // bandwidth = 0: z = -depth + amplitude cos(t + asymmetry sin t), the float32 of the double sum,
  // bit for bit (the ripples' formula before ripple fields had a spectral width).
  BathyGenSpec s = base_spec(30.0, 20.0, 0.25);
  bathy::Ripples r;
  r.wavelength_m = 1.7;
  r.amplitude_m = 0.08;
  r.crest_azimuth_rad = 0.4;
  r.asymmetry = 0.35;
  r.ref_x_m = 1.5;
  r.ref_y_m = -2.0;
  r.bandwidth = 0.0;
  s.components.push_back(r);
  const HeightGrid g = generate_bathymetry(s);
  const GridGeometry& geo = g.geometry();
  const double nx = std::cos(r.crest_azimuth_rad), ny = -std::sin(r.crest_azimuth_rad);
  const double k = 2.0 * kPi / r.wavelength_m;
  for (std::size_t row = 0; row < geo.rows; ++row) {
    const double y = geo.y_of_row(static_cast<double>(row));
    for (std::size_t c = 0; c < geo.cols; ++c) {
      const double x = geo.x0_m + static_cast<double>(c) * geo.dx_m;
      const double t = k * (nx * (x - r.ref_x_m) + ny * (y - r.ref_y_m));
      const double z = -20.0 + r.amplitude_m * std::cos(t + r.asymmetry * std::sin(t));
      ASSERT_EQ(g.node(c, row), static_cast<float>(z)) << c << "," << row;
    }
  }
}

// In-place radix-2 FFT (n a power of two), independent of the generator's code.
void fft(std::vector<std::complex<double>>& a) {
  const std::size_t n = a.size();
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(a[i], a[j]);
  }
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const double ang = -2.0 * kPi / static_cast<double>(len);
    const std::complex<double> wl(std::cos(ang), std::sin(ang));
    for (std::size_t i = 0; i < n; i += len) {
      std::complex<double> w(1.0, 0.0);
      for (std::size_t j = 0; j < len / 2; ++j) {
        const std::complex<double> u = a[i + j], v = a[i + j + len / 2] * w;
        a[i + j] = u + v;
        a[i + j + len / 2] = u - v;
        w *= wl;
      }
    }
  }
}

struct RippleSpectrum {
  double peak_k;        // |centroid| of the power over the half-plane k . n > 0, rad/m
  double peak_azimuth;  // grid azimuth of the crests the centroid implies, rad
  double across_rel;    // rms width along n (across the crests) / peak_k
  double along_rel;     // rms width along the crests / peak_k
};

// The 2-D power spectrum of the heights (Hann-windowed, mean removed) and its first and second
// moments over the half-plane towards n within |k| < 1.6 k0 (leaving out the harmonics), with
// the Hann window's own spectral variance (1/3 bin^2 per axis) subtracted.
RippleSpectrum ripple_spectrum(const HeightGrid& g, double k0, double crest_azimuth_rad) {
  const GridGeometry& geo = g.geometry();
  const std::size_t n = geo.cols;  // square, a power of two
  double mean = 0.0;
  for (float h : g.heights()) mean += h;
  mean /= static_cast<double>(g.heights().size());
  std::vector<std::complex<double>> a(n * n);
  const auto hann = [n](std::size_t i) {
    const double s = std::sin(kPi * static_cast<double>(i) / static_cast<double>(n));
    return s * s;
  };
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t c = 0; c < n; ++c) a[r * n + c] = (g.node(c, r) - mean) * hann(r) * hann(c);
  }
  std::vector<std::complex<double>> line(n);
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t c = 0; c < n; ++c) line[c] = a[r * n + c];
    fft(line);
    for (std::size_t c = 0; c < n; ++c) a[r * n + c] = line[c];
  }
  for (std::size_t c = 0; c < n; ++c) {
    for (std::size_t r = 0; r < n; ++r) line[r] = a[r * n + c];
    fft(line);
    for (std::size_t r = 0; r < n; ++r) a[r * n + c] = line[r];
  }
  const double dk = 2.0 * kPi / (static_cast<double>(n) * geo.dx_m);
  const double nx = std::cos(crest_azimuth_rad), ny = -std::sin(crest_azimuth_rad);
  double p0 = 0.0, px = 0.0, py = 0.0, pxx = 0.0, pyy = 0.0, pxy = 0.0;
  const auto freq = [n](std::size_t i) {
    return i < n / 2 ? static_cast<double>(i) : static_cast<double>(i) - static_cast<double>(n);
  };
  for (std::size_t r = 0; r < n; ++r) {
    // Row index runs south (dy < 0): the wavenumber along +y is minus the row frequency.
    const double ky = -freq(r) * dk;
    for (std::size_t c = 0; c < n; ++c) {
      const double kx = freq(c) * dk;
      if (kx * nx + ky * ny <= 0.0 || std::hypot(kx, ky) > 1.6 * k0) continue;
      const double p = std::norm(a[r * n + c]);
      p0 += p;
      px += p * kx;
      py += p * ky;
      pxx += p * kx * kx;
      pyy += p * ky * ky;
      pxy += p * kx * ky;
    }
  }
  const double cx = px / p0, cy = py / p0;
  const double vxx = pxx / p0 - cx * cx, vyy = pyy / p0 - cy * cy, vxy = pxy / p0 - cx * cy;
  const double k = std::hypot(cx, cy);
  const double ux = cx / k, uy = cy / k;  // across the crests
  const double window = dk * dk / 3.0;
  const double across = ux * ux * vxx + 2.0 * ux * uy * vxy + uy * uy * vyy - window;
  const double along = uy * uy * vxx - 2.0 * ux * uy * vxy + ux * ux * vyy - window;
  // n = (cos a, -sin a): a = atan2(-uy, ux).
  return {k, std::atan2(-uy, ux), std::sqrt(across) / k, std::sqrt(along) / k};
}

TEST(BathyGen, RippleFieldSpectrumHasTheConfiguredPeakAndWidth) {
  // 512 x 512 nodes at 0.25 m: k0 = 2 pi / 2 m, a bin 0.049 rad/m, sigma_k = 0.1 k0 = 6.4 bins.
  // A Gaussian field (amplitude_variation 1) has the Gaussian spectrum of rms width bandwidth k0
  // per axis in expectation; one realisation of 96 modes is within ~1/sqrt(2 x 96) = 7 % of it.
  // The default envelope (v = 0.5) widens it a little (the envelope is a nonlinear function).
  for (const double v : {1.0, 0.5}) {
    for (const double bandwidth : {0.1, 0.2}) {
      BathyGenSpec s = base_spec(128.0, 128.0, 0.25);
      bathy::Ripples r;
      r.wavelength_m = 2.0;
      r.amplitude_m = 0.05;
      r.crest_azimuth_rad = rad_from_deg(25.0);
      r.bandwidth = bandwidth;
      r.amplitude_variation = v;
      s.components.push_back(r);
      const HeightGrid g = generate_bathymetry(s);
      ASSERT_EQ(g.geometry().cols, 512u);
      const double k0 = kPi;
      const RippleSpectrum sp = ripple_spectrum(g, k0, r.crest_azimuth_rad);
      std::cout << "v " << v << " bandwidth " << bandwidth << ": peak k / k0 " << sp.peak_k / k0
                << ", crest azimuth " << deg_from_rad(sp.peak_azimuth) << " deg, width across "
                << sp.across_rel << ", along " << sp.along_rel << "\n";
      EXPECT_NEAR(sp.peak_k / k0, 1.0, 0.03);
      // The centroid of 96 modes: within 3 standard errors, 3 bandwidth / sqrt(96) radians.
      EXPECT_NEAR(deg_from_rad(sp.peak_azimuth), 25.0, 0.5 + deg_from_rad(0.31 * bandwidth));
      const double tol = v == 1.0 ? 0.2 : 0.35;
      EXPECT_NEAR(sp.across_rel / bandwidth, 1.0, tol);
      EXPECT_NEAR(sp.along_rel / bandwidth, 1.0, tol);
      // The mean square height is amplitude^2 / 2, as for the sinusoid.
      double sum2 = 0.0;
      for (float h : g.heights()) sum2 += (h + 20.0) * (h + 20.0);
      const double rms = std::sqrt(sum2 / static_cast<double>(g.heights().size()));
      EXPECT_NEAR(rms / (0.05 / std::sqrt(2.0)), 1.0, 0.15);
    }
  }
  // The pure sinusoid: a single line (widths within the window's leakage).
  BathyGenSpec s = base_spec(128.0, 128.0, 0.25);
  bathy::Ripples r;
  r.wavelength_m = 2.0;
  r.crest_azimuth_rad = rad_from_deg(25.0);
  r.bandwidth = 0.0;
  s.components.push_back(r);
  const RippleSpectrum sp = ripple_spectrum(generate_bathymetry(s), kPi, r.crest_azimuth_rad);
  EXPECT_NEAR(sp.peak_k / kPi, 1.0, 0.01);
  EXPECT_LT(sp.across_rel, 0.02);
  EXPECT_LT(sp.along_rel, 0.02);
}

TEST(BathyGen, RippleFieldDependsOnSeedAndOffset) {
  BathyGenSpec s = base_spec(20.0, 20.0, 0.25);
  s.components.push_back(bathy::Ripples{});
  const HeightGrid a = generate_bathymetry(s);
  EXPECT_TRUE(bit_identical(a, generate_bathymetry(s)));
  std::get<bathy::Ripples>(s.components[0]).seed_offset = 1;
  EXPECT_FALSE(bit_identical(a, generate_bathymetry(s)));
  s.seed = 43;
  std::get<bathy::Ripples>(s.components[0]).seed_offset = 0;
  EXPECT_FALSE(bit_identical(a, generate_bathymetry(s)));
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
