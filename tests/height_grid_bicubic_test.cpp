// SPDX-License-Identifier: MIT
// The bicubic (cubic convolution, a = -0.5) surface of a HeightGrid, checked against what defines
// it: it passes through the nodes, reproduces quadratics (and not cubics: third-order
// convergence), is C1 across grid lines, and keeps the holes of the bilinear surface
// (docs/physics.md, "Seabed interpolation").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include "height_grid_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/height_grid.hpp"

namespace sonarsynth {
namespace {

constexpr float kHole = std::numeric_limits<float>::quiet_NaN();

HeightGrid make_grid(const GridGeometry& g, const std::function<double(double, double)>& f,
                     Interpolation interpolation = Interpolation::kBicubic) {
  HeightGrid grid = test::sampled_grid(g, f);
  grid.set_interpolation(interpolation);
  return grid;
}

// Random heights (float32), north-up, non-square cells.
HeightGrid random_grid(std::size_t cols, std::size_t rows, std::uint32_t seed) {
  const GridGeometry g{-3.0, 7.0, 2.0, -1.5, cols, rows};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-30.0, -10.0);
  return make_grid(g, [&](double, double) { return u(rng); });
}

TEST(HeightGridBicubic, PassesThroughEveryNodeIncludingTheBorders) {
  for (const auto& [cols, rows] : {std::pair<std::size_t, std::size_t>{9, 7}, {2, 2}, {3, 2}}) {
    const HeightGrid grid = random_grid(cols, rows, 3);
    const GridGeometry& g = grid.geometry();
    for (std::size_t r = 0; r < rows; ++r) {
      for (std::size_t c = 0; c < cols; ++c) {
        const double x = g.x_of_col(static_cast<double>(c)), y = g.y_of_row(static_cast<double>(r));
        EXPECT_NEAR(grid.height_m(x, y), grid.node(c, r), 1e-12) << c << "," << r;
      }
    }
  }
}

TEST(HeightGridBicubic, ReproducesQuadraticsEverywhereButNotCubics) {
  // Coefficients and node coordinates are multiples of powers of two: the node heights are
  // exact in float32, so the surface must equal the quadratic to round-off, border cells included
  // (the extrapolated outer row/column, 3 f0 - 3 f1 + f2, is exact for quadratics).
  const GridGeometry g{-8.0, 6.0, 0.5, -0.25, 33, 49};
  const auto q = [](double x, double y) {
    return -20.0 + 0.25 * x - 0.5 * y + 0.125 * x * x - 0.0625 * x * y + 0.25 * y * y;
  };
  const HeightGrid grid = make_grid(g, q);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(-8.0, 8.0), uy(-6.0, 6.0);
  for (int i = 0; i < 4000; ++i) {
    const double x = ux(rng), y = uy(rng);
    const HeightSample s = grid.sample(x, y);
    EXPECT_NEAR(s.z_m, q(x, y), 1e-11) << x << "," << y;
    EXPECT_NEAR(s.dzdx, 0.25 + 0.25 * x - 0.0625 * y, 1e-10);
    EXPECT_NEAR(s.dzdy, -0.5 - 0.0625 * x + 0.5 * y, 1e-10);
  }
  // A cubic is not reproduced, and the error of a smooth surface falls as h^3 (third order).
  const auto f = [](double x, double y) { return std::sin(0.7 * x) * std::cos(0.5 * y); };
  auto worst = [&](double h) {
    const auto n = static_cast<std::size_t>(std::llround(16.0 / h)) + 1;
    const HeightGrid s = make_grid({-8.0, 8.0, h, -h, n, n}, f);
    double e = 0.0;
    for (double x = -5.0; x <= 5.0; x += 0.0137) {
      for (double y = -5.0; y <= 5.0; y += 0.291)
        e = std::max(e, std::abs(s.height_m(x, y) - f(x, y)));
    }
    return e;
  };
  const double e1 = worst(0.5), e2 = worst(0.25);
  EXPECT_GT(e1, 1e-4);  // not exact
  EXPECT_GT(e1 / e2, 6.5);
  EXPECT_LT(e1 / e2, 10.0);
  const HeightGrid cubic = make_grid(g, [](double x, double) { return 0.125 * x * x * x; });
  EXPECT_GT(std::abs(cubic.height_m(0.1, 0.0) - 0.125 * 0.001), 1e-6);
}

TEST(HeightGridBicubic, SlopeIsContinuousAcrossGridLinesUnlikeBilinear) {
  const HeightGrid cubic = random_grid(12, 10, 9);
  HeightGrid linear = cubic;
  linear.set_interpolation(Interpolation::kBilinear);
  const GridGeometry& g = cubic.geometry();
  const double eps = 1e-6;
  double worst_jump = 0.0, bilinear_jump = 0.0, worst_fd = 0.0;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> frac(0.0, 1.0);
  for (std::size_t c = 1; c + 1 < g.cols; ++c) {
    for (int k = 0; k < 20; ++k) {
      // A point on the vertical grid line of column c, anywhere along it (border rows included).
      const double x = g.x_of_col(static_cast<double>(c));
      const double y = g.y_of_row(frac(rng) * static_cast<double>(g.rows - 1));
      // Finite-difference slopes from either side.
      const double left = (cubic.height_m(x, y) - cubic.height_m(x - eps, y)) / eps;
      const double right = (cubic.height_m(x + eps, y) - cubic.height_m(x, y)) / eps;
      worst_jump = std::max(worst_jump, std::abs(right - left));
      const double bl = (linear.height_m(x, y) - linear.height_m(x - eps, y)) / eps;
      const double br = (linear.height_m(x + eps, y) - linear.height_m(x, y)) / eps;
      bilinear_jump = std::max(bilinear_jump, std::abs(br - bl));
      // The analytic gradient agrees with the finite difference.
      worst_fd = std::max(worst_fd, std::abs(cubic.sample(x + 0.5 * eps, y).dzdx - right));
    }
  }
  for (std::size_t r = 1; r + 1 < g.rows; ++r) {
    for (int k = 0; k < 20; ++k) {
      const double y = g.y_of_row(static_cast<double>(r));
      const double x = g.x_of_col(frac(rng) * static_cast<double>(g.cols - 1));
      const double dy = g.dy_m > 0 ? eps : -eps;  // step to the next row and back
      const double before = (cubic.height_m(x, y) - cubic.height_m(x, y - dy)) / dy;
      const double after = (cubic.height_m(x, y + dy) - cubic.height_m(x, y)) / dy;
      worst_jump = std::max(worst_jump, std::abs(after - before));
      worst_fd = std::max(worst_fd, std::abs(cubic.sample(x, y + 0.5 * dy).dzdy - after));
    }
  }
  // Slopes are O(10) (heights in [-30, -10] over 1.5-2 m cells): a jump would be O(1).
  EXPECT_LT(worst_jump, 1e-3);
  EXPECT_LT(worst_fd, 1e-3);
  EXPECT_GT(bilinear_jump, 1.0);  // the same check sees the bilinear surface's kinks
}

TEST(HeightGridBicubic, HolesStayHolesAndCellsNearThemAreBilinear) {
  HeightGrid cubic = random_grid(10, 9, 4);
  cubic.mutable_heights()[4 * 10 + 5] = kHole;
  cubic.mutable_heights()[0 * 10 + 0] = kHole;  // a corner hole: the extrapolation sees it
  HeightGrid linear = cubic;
  linear.set_interpolation(Interpolation::kBilinear);
  const GridGeometry& g = cubic.geometry();
  std::size_t holes = 0, near_hole = 0;
  for (double fc = 0.0; fc <= 9.0; fc += 0.0625) {
    for (double fr = 0.0; fr <= 8.0; fr += 0.0625) {
      const double x = g.x_of_col(fc), y = g.y_of_row(fr);
      const double zc = cubic.height_m(x, y), zl = linear.height_m(x, y);
      EXPECT_EQ(std::isnan(zc), std::isnan(zl)) << fc << "," << fr;
      if (std::isnan(zl)) {
        ++holes;
        continue;
      }
      // Cells whose 4 x 4 stencil holds the hole at (5, 4) but not as a corner: bilinear.
      const double c0 = std::min(std::floor(fc), 8.0), r0 = std::min(std::floor(fr), 7.0);
      if (c0 >= 3 && c0 <= 6 && r0 >= 2 && r0 <= 5) {
        EXPECT_DOUBLE_EQ(zc, zl);
        ++near_hole;
      }
    }
  }
  EXPECT_GT(holes, 0u);
  EXPECT_GT(near_hole, 0u);
  // Outside the node area: NaN, as bilinear.
  EXPECT_TRUE(std::isnan(cubic.height_m(g.x_of_col(-0.01), g.y_of_row(3.0))));
}

TEST(HeightGridBicubic, ProfileSamplesEachCellFinelyAndCostsTheCellsItCrosses) {
  const GridGeometry g{0.0, 80.0, 8.0, -8.0, 11, 11};  // 8 m cells, north-up
  const HeightGrid grid =
      make_grid(g, [](double x, double y) { return -30.0 + 3.0 * std::sin(x / 9.0 + y / 13.0); });
  HeightGrid linear = grid;
  linear.set_interpolation(Interpolation::kBilinear);
  const Eigen::Vector2d start(3.0, 41.0);
  const Eigen::Vector2d dir = Eigen::Vector2d(0.8, -0.6);  // unit
  const double length = 70.0;
  std::vector<ProfilePoint> pts, lin;
  grid.profile(start, dir, length, 1, pts);
  linear.profile(start, dir, length, 1, lin);
  // Every point is the surface's height at its position.
  for (const ProfilePoint& p : pts) {
    const Eigen::Vector2d q = start + p.s_m * dir;
    if (std::isnan(p.z_m)) {
      EXPECT_TRUE(std::isnan(grid.height_m(q.x(), q.y())));
    } else {
      EXPECT_DOUBLE_EQ(p.z_m, grid.height_m(q.x(), q.y()));
    }
  }
  // Steps: at most 1/8 cell along x (the axis the line runs closest to: 0.8 / 8 > 0.6 / 8).
  const double max_step = 8.0 / 0.8 / HeightGrid::kBicubicSegmentsPerCell;
  for (std::size_t k = 1; k < pts.size(); ++k) {
    EXPECT_GT(pts[k].s_m, pts[k - 1].s_m);
    EXPECT_LE(pts[k].s_m - pts[k - 1].s_m, max_step * (1 + 1e-9));
  }
  // The bilinear profile's points (the crossings) are among them, and there are at most 8 per
  // crossing plus one.
  for (const ProfilePoint& p : lin) {
    EXPECT_TRUE(std::any_of(pts.begin(), pts.end(), [&](const ProfilePoint& q) {
      return std::abs(q.s_m - p.s_m) < 1e-9;
    })) << p.s_m;
  }
  EXPECT_LE(pts.size(), HeightGrid::kBicubicSegmentsPerCell * (lin.size() - 1) + 1);
  auto chord_error = [&](const HeightGrid& s, const std::vector<ProfilePoint>& v) {
    double e = 0.0;
    for (std::size_t k = 1; k < v.size(); ++k) {
      const double sm = 0.5 * (v[k].s_m + v[k - 1].s_m);
      const Eigen::Vector2d q = start + sm * dir;
      e = std::max(e, std::abs(0.5 * (v[k].z_m + v[k - 1].z_m) - s.height_m(q.x(), q.y())));
    }
    return e;
  };
  // The chords follow the surface: midpoint error <= max |d2z/ds2| h^2 / 8 (the curvature of
  // the bicubic surface along the line, by central differences), h = the longest step.
  double curvature = 0.0;
  for (double sm = 0.01; sm < length - 0.01; sm += 0.005) {
    const auto z = [&](double t) {
      const Eigen::Vector2d q = start + t * dir;
      return grid.height_m(q.x(), q.y());
    };
    const double d2 = (z(sm + 0.005) - 2 * z(sm) + z(sm - 0.005)) / (0.005 * 0.005);
    if (std::isfinite(d2)) curvature = std::max(curvature, std::abs(d2));
  }
  const double bound = curvature * max_step * max_step / 8.0;
  EXPECT_LT(chord_error(grid, pts), bound * 1.05);
  EXPECT_LT(bound, 0.02);  // 1.25 m steps: within 2 cm of the smooth surface
  // The bilinear chords (whole crossings) are farther from the bicubic surface.
  EXPECT_GT(chord_error(grid, lin), 4.0 * chord_error(grid, pts));
  // A higher subdivision count is honoured (at least 16 per cell).
  std::vector<ProfilePoint> fine;
  grid.profile(start, dir, length, 16, fine);
  EXPECT_GT(fine.size(), pts.size() * 3 / 2);
}

TEST(HeightGridBicubic, RefinedGeometryAndResample) {
  const GridGeometry g{100.0, 500.0, 8.0, -8.0, 6, 5};  // spans 40 x 32 m
  const GridGeometry f = refined_geometry(g, 0.25);
  EXPECT_EQ(f.cols, 161u);
  EXPECT_EQ(f.rows, 129u);
  EXPECT_EQ(f.x0_m, g.x0_m);
  EXPECT_EQ(f.y0_m, g.y0_m);
  EXPECT_EQ(f.dx_m, 0.25);
  EXPECT_EQ(f.dy_m, -0.25);
  const GridGeometry odd = refined_geometry(g, 3.0);  // 40 / 3 = 13.3: 14 nodes, last at 39 m
  EXPECT_EQ(odd.cols, 14u);
  EXPECT_EQ(odd.rows, 11u);
  EXPECT_THROW(refined_geometry(g, 0.0), InputError);
  EXPECT_THROW(refined_geometry(g, std::nan("")), InputError);
  // Resampling a quadratic: the nodes of the fine grid hold the quadratic, and the result is a
  // bilinear grid; the thread count does not change a byte.
  const auto q = [](double x, double y) {
    return -20.0 + 0.01 * (x - 120.0) * (x - 120.0) - 0.02 * (y - 484.0) * (x - 120.0);
  };
  const HeightGrid coarse = make_grid(g, q);
  const HeightGrid fine = resample(coarse, f, 1);
  EXPECT_EQ(fine.interpolation(), Interpolation::kBilinear);
  for (std::size_t r = 0; r < f.rows; r += 7) {
    for (std::size_t c = 0; c < f.cols; c += 5) {
      const double x = f.x_of_col(static_cast<double>(c)), y = f.y_of_row(static_cast<double>(r));
      EXPECT_NEAR(fine.node(c, r), q(x, y), 2e-5);
    }
  }
  EXPECT_EQ(resample(coarse, f, 3).heights(), fine.heights());
}

}  // namespace
}  // namespace sonarsynth
