// SPDX-License-Identifier: MIT
#include "sonarsynth/height_grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include "height_grid_test_util.hpp"
#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace {

// A grid sampled from an analytic surface f(x, y) at its nodes.
using test::sampled_grid;

// North-up like a GDAL raster: negative dy, origin at the north-west node.
// n x n nodes centred on the local origin.
GridGeometry north_up(double cell, std::size_t n) {
  const double half = cell * static_cast<double>(n - 1) / 2.0;
  return {-half, half, cell, -cell, n, n};
}

TEST(HeightGrid, PlaneIsExactIncludingGradientAndNormal) {
  const double a = 0.1, b = -0.05, c = -20.0;
  const HeightGrid grid =
      sampled_grid(north_up(0.5, 201), [&](double x, double y) { return a * x + b * y + c; });
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-49.9, 49.9);
  for (int i = 0; i < 1000; ++i) {
    const double x = u(rng), y = u(rng);
    const HeightSample s = grid.sample(x, y);
    // float32 storage of heights ~20 m: 2e-6 m resolution.
    EXPECT_NEAR(s.z_m, a * x + b * y + c, 1e-5);
    EXPECT_NEAR(s.dzdx, a, 1e-5);
    EXPECT_NEAR(s.dzdy, b, 1e-5);
    const Eigen::Vector3d n_true = Eigen::Vector3d(-a, -b, 1.0).normalized();
    EXPECT_LT((s.normal() - n_true).norm(), 1e-5);
  }
}

TEST(HeightGrid, ParaboloidWithinBilinearErrorBound) {
  // z = k (x^2 + y^2): bilinear interpolation error <= k h^2 / 2, gradient error <= 2 k h / 2.
  const double k = 0.01, h = 0.5;
  const HeightGrid grid =
      sampled_grid(north_up(h, 201), [&](double x, double y) { return k * (x * x + y * y); });
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-49.0, 49.0);
  double worst_z = 0, worst_g = 0;
  for (int i = 0; i < 2000; ++i) {
    const double x = u(rng), y = u(rng);
    const HeightSample s = grid.sample(x, y);
    worst_z = std::max(worst_z, std::abs(s.z_m - k * (x * x + y * y)));
    worst_g = std::max({worst_g, std::abs(s.dzdx - 2 * k * x), std::abs(s.dzdy - 2 * k * y)});
  }
  EXPECT_LE(worst_z, k * h * h / 2 + 1e-4);
  EXPECT_LE(worst_g, k * h + 1e-5);
  // At nodes the surface is exact (to float32).
  EXPECT_NEAR(grid.height_m(10.0, -20.0), k * 500.0, 1e-5);
  // Normal at a node-free point: angle error below the gradient bound.
  const HeightSample s = grid.sample(30.25, 30.25);
  const Eigen::Vector3d n_true = Eigen::Vector3d(-2 * k * 30.25, -2 * k * 30.25, 1).normalized();
  EXPECT_LT(std::acos(std::min(1.0, s.normal().dot(n_true))), k * h * 1.5);
}

TEST(HeightGrid, HolesAndOutsideAreNaN) {
  HeightGrid grid = sampled_grid(north_up(1.0, 11), [](double, double) { return -10.0; });
  grid.mutable_heights()[5 * 11 + 5] = std::numeric_limits<float>::quiet_NaN();  // node (0, 0)
  EXPECT_TRUE(std::isnan(grid.height_m(0.0, 0.0)));
  EXPECT_TRUE(std::isnan(grid.height_m(0.5, 0.5)));  // a cell touching the hole
  EXPECT_TRUE(std::isnan(grid.height_m(-0.5, -0.5)));
  EXPECT_FALSE(std::isnan(grid.height_m(1.5, 1.5)));   // cells not touching it are fine
  EXPECT_TRUE(std::isnan(grid.height_m(-5.01, 0.0)));  // outside
  EXPECT_EQ(grid.count_valid(), 120u);
  // Grid edges are inside (inclusive).
  EXPECT_NEAR(grid.height_m(-5.0, 5.0), -10.0, 1e-6);
  EXPECT_NEAR(grid.height_m(5.0, -5.0), -10.0, 1e-6);
}

TEST(HeightGrid, ProfileHitsEveryGridLineAndMatchesPointQueries) {
  const double k = 0.01;
  const HeightGrid grid =
      sampled_grid(north_up(0.5, 201), [&](double x, double y) { return k * (x * x + y * y); });
  const Eigen::Vector2d start(-3.1, 2.7);
  const Eigen::Vector2d dir = Eigen::Vector2d(0.8, -0.6);  // unit
  std::vector<ProfilePoint> prof;
  grid.profile(start, dir, 30.0, 1, prof);
  // Independent count of grid-line crossings: every column and row line tried by brute force.
  // |dx| = 24 m crosses 48 column lines, |dy| = 18 m 36 row lines; 12 of them meet at nodes.
  std::vector<double> expected = {0.0, 30.0};
  for (int i = 0; i < 201; ++i) {
    const double line = -50.0 + 0.5 * i;
    for (double s : {(line - start.x()) / dir.x(), (line - start.y()) / dir.y()}) {
      if (s > 0.0 && s < 30.0) expected.push_back(s);
    }
  }
  std::sort(expected.begin(), expected.end());
  expected.erase(std::unique(expected.begin(), expected.end(),
                             [](double a, double b) { return std::abs(a - b) < 1e-9; }),
                 expected.end());
  EXPECT_EQ(expected.size(), 48u + 36u - 12u + 2u);
  ASSERT_EQ(prof.size(), expected.size());
  for (std::size_t i = 0; i < prof.size(); ++i) EXPECT_NEAR(prof[i].s_m, expected[i], 1e-9);
  for (std::size_t i = 1; i < prof.size(); ++i) EXPECT_GT(prof[i].s_m, prof[i - 1].s_m);
  EXPECT_DOUBLE_EQ(prof.front().s_m, 0.0);
  EXPECT_DOUBLE_EQ(prof.back().s_m, 30.0);
  for (const ProfilePoint& p : prof) {
    const Eigen::Vector2d xy = start + p.s_m * dir;
    EXPECT_DOUBLE_EQ(p.z_m, grid.height_m(xy.x(), xy.y()));
  }
  // Subdivisions: the chord between points converges to the bilinear surface.
  std::vector<ProfilePoint> fine;
  grid.profile(start, dir, 30.0, 4, fine);
  EXPECT_GE(fine.size(), 4 * (prof.size() - 1));
}

TEST(HeightGrid, ProfileLeavingTheGridGivesNaN) {
  const HeightGrid grid = sampled_grid(north_up(1.0, 21), [](double, double) { return -5.0; });
  std::vector<ProfilePoint> prof;
  grid.profile({0.0, 0.0}, {1.0, 0.0}, 100.0, 1, prof);
  ASSERT_FALSE(prof.empty());
  EXPECT_FALSE(std::isnan(prof.front().z_m));
  EXPECT_TRUE(std::isnan(prof.back().z_m));
}

TEST(HeightGrid, AProfileCostsTheGridLinesItCrossesNotItsLengthOverCells) {
  // 4 x 4 nodes 1 um apart and a 30 m ray across them along a row: the points are the two ends
  // and at most the 4 column lines of the grid, not 30 m / 1 um of empty crossings.
  const GridGeometry g = north_up(1e-6, 4);
  const HeightGrid grid = sampled_grid(g, [](double, double) { return -5.0; });
  std::vector<ProfilePoint> prof;
  grid.profile({g.x_of_col(1.5) - 15.0, g.y_of_row(1.5)}, {1.0, 0.0}, 30.0, 1, prof);
  EXPECT_LE(prof.size(), 6u);
  std::size_t valid = 0;
  for (const auto& p : prof) valid += !std::isnan(p.z_m);
  EXPECT_GE(valid, 2u);  // at least the two inner column lines
}

TEST(HeightGrid, RejectsBadGeometry) {
  EXPECT_THROW(HeightGrid(GridGeometry{0, 0, 0.0, -1.0, 2, 2}, std::vector<float>(4)), InputError);
  EXPECT_THROW(HeightGrid(GridGeometry{0, 0, -1.0, -1.0, 2, 2}, std::vector<float>(4)), InputError);
  EXPECT_THROW(HeightGrid(GridGeometry{0, 0, 1.0, -1.0, 2, 2}, std::vector<float>(3)), InputError);
  EXPECT_THROW(HeightGrid(GridGeometry{0, 0, 1.0, -1.0, 1, 5}, std::vector<float>(5)), InputError);
}

TEST(HeightGrid, BadGeometryNamesTheField) {
  try {
    GridGeometry{0, 0, 1.0, 0.0, 2, 2}.validate("grid");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("grid: cell size y: dy_m = 0"), std::string::npos)
        << e.what();
  }
  try {
    GridGeometry{std::nan(""), 0, 1.0, -1.0, 2, 2}.validate("grid");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("grid: x0_m = nan"), std::string::npos) << e.what();
  }
}

TEST(HeightGrid, SeabedRulesOfEveryGrid) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const GridGeometry g{0, 0, 1.0, -1.0, 3, 3};
  EXPECT_NE(seabed_grid_problem(g, std::vector<float>(9, nan)).find("every node is nodata"),
            std::string::npos);
  // A checkerboard: 5 valid nodes, no cell with 4.
  const std::vector<float> board = {-1, nan, -1, nan, -1, nan, -1, nan, -1};
  EXPECT_NE(seabed_grid_problem(g, board).find("5 valid nodes but no 2 x 2 block"),
            std::string::npos);
  // One valid cell in the last corner is enough.
  EXPECT_EQ(seabed_grid_problem(g, {nan, nan, nan, nan, -1, -1, nan, -1, -1}), "");
  // Heights beyond the deepest ocean and the highest land are no heights.
  EXPECT_TRUE(is_height(-12000.0f));
  EXPECT_FALSE(is_height(12000.5f));
  EXPECT_FALSE(is_height(std::numeric_limits<float>::infinity()));
  EXPECT_FALSE(is_height(nan));
  // Wholly above sea level is refused; one node at or below it is enough.
  EXPECT_NE(seabed_above_sea_level_problem(50.0, 60.0)
                .find("above sea level everywhere (heights "
                      "50 .. 60 m)"),
            std::string::npos);
  EXPECT_EQ(seabed_above_sea_level_problem(0.0, 60.0), "");
  EXPECT_EQ(seabed_above_sea_level_problem(-20.0, 60.0), "");
}

}  // namespace
}  // namespace sonarsynth
