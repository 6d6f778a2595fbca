// SPDX-License-Identifier: MIT
// Shadows of the per-side renderer against their analytic intervals (docs/physics.md §3): boxes,
// pipes, posts, and shadows switched off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "analytic/flat_seabed.hpp"
#include "render_side_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/render_math.hpp"
#include "sonarsynth/render_side.hpp"

namespace sonarsynth {
namespace {

constexpr double kPiT = 3.14159265358979323846;
using test::base_params;
using test::box_profile;
using test::plane_profile;

// The dark (zero) run of samples after the first return: [start, end) in metres.
std::pair<double, double> dark_interval(const SideEcho& e, double dr) {
  std::size_t i = 0;
  while (i < e.intensity.size() && e.intensity[i] == 0.0) ++i;
  while (i < e.intensity.size() && e.intensity[i] > 0.0) ++i;
  const std::size_t start = i;
  while (i < e.intensity.size() && e.intensity[i] == 0.0) ++i;
  return {static_cast<double>(start) * dr, static_cast<double>(i) * dr};
}

TEST(RenderSide, BoxShadowInterval) {
  const double h = 10.0, box_h = 1.0, y_b = 32.0, dr = 0.02;
  SideParams p = base_params(dr, 2500);
  p.truth = true;
  SideEcho e;
  render_side(box_profile(h, box_h, 30.0, y_b, 50.0, 0.1), p, e);
  const auto [d0, d1] = dark_interval(e, dr);
  const double r_top = std::sqrt(y_b * y_b + (h - box_h) * (h - box_h));  // 33.242
  const double r_end = r_top * h / (h - box_h);                           // 36.935
  EXPECT_NEAR(r_top, 33.242, 1e-3);
  EXPECT_NEAR(r_end, 36.935, 1e-3);
  EXPECT_NEAR(d0, r_top, dr);
  EXPECT_NEAR(d1, r_end, dr);
  // Truth: the dark samples are shadow; the front face and top are the object.
  for (double r = d0 + dr; r < d1 - dr; r += dr) {
    EXPECT_EQ(e.truth_class[static_cast<std::size_t>(r / dr)], SampleClass::shadow) << r;
  }
  const auto top = static_cast<std::size_t>(32.5 / dr);  // top of the box at ~ r 31.3-33.2
  EXPECT_EQ(e.truth_class[top], SampleClass::object);
  EXPECT_EQ(e.truth_label[top], 7);
}

TEST(RenderSide, ShadowsOffLightsTheBackRegion) {
  const double dr = 0.02;
  SideParams p = base_params(dr, 2500);
  p.shadows = false;
  SideEcho e;
  render_side(box_profile(10.0, 1.0, 30.0, 32.0, 50.0, 0.1), p, e);
  // The back wall (33.242 .. 33.53 m) faces away and stays dark; the seabed behind it is lit.
  for (double r = 33.6; r < 36.8; r += dr) {
    EXPECT_GT(e.intensity[static_cast<std::size_t>(r / dr)], 0.0) << r;
  }
}

TEST(RenderSide, PipeShadowInterval) {
  const double h = 10.0, a = 0.5, yc = 30.0, dr = 0.02;
  // Pipe lying on the seabed (centre at height a): the heightfield is the upper half-circle
  // plus vertical walls down to the seabed at y = yc -+ a (the filled underside).
  BeamProfile prof;
  prof.sensor_z_m = h;
  for (double y = 0.0; y < yc - a; y += 0.1) prof.add_node(y, 0.0);
  prof.add_node(yc - a, 0.0);
  const int segs = 2000;
  for (int k = 0; k <= segs; ++k) {
    const double ang = kPiT * (1.0 - static_cast<double>(k) / segs);
    prof.add_node(yc + a * std::cos(ang), a + a * std::sin(ang), 3);
  }
  prof.add_node(yc + a, 0.0, 3);
  for (double y = yc + a + 0.1; y <= 45.0; y += 0.1) prof.add_node(y, 0.0);
  SideParams p = base_params(dr, 2000);
  SideEcho e;
  render_side(prof, p, e);
  const double d = std::sqrt(yc * yc + (h - a) * (h - a));
  const double theta_t = std::atan2(h - a, yc) - std::asin(a / d);
  const double y_e = h / std::tan(theta_t);
  const double r_t = std::sqrt(d * d - a * a), r_e = std::sqrt(y_e * y_e + h * h);
  EXPECT_NEAR(r_t, 31.464, 1e-3);
  EXPECT_NEAR(r_e, 34.879, 1e-3);
  const auto [d0, d1] = dark_interval(e, dr);
  EXPECT_NEAR(d0, r_t, dr);
  EXPECT_NEAR(d1, r_e, dr);
}

TEST(RenderSide, PostTopReturnsBeforeSeabedAtItsBase) {
  const double h = 10.0, post_h = 3.0, y = 40.0, dr = 0.02;
  SideParams p = base_params(dr, 2500);
  p.truth = true;
  SideEcho flat, post;
  render_side(plane_profile(h, 0.0, 50.0, 0.1), p, flat);
  render_side(box_profile(h, post_h, y, y + 0.1, 50.0, 0.1, 11), p, post);
  const double r_top = std::sqrt(y * y + (h - post_h) * (h - post_h));  // 40.608
  const double r_base = std::sqrt(y * y + h * h);                       // 41.231
  // The first sample where the post changes the echo contains the post top's range.
  std::size_t first_diff = 0;
  while (first_diff < p.samples &&
         std::abs(post.intensity[first_diff] - flat.intensity[first_diff]) <=
             1e-6 * flat.intensity[first_diff]) {
    ++first_diff;
  }
  EXPECT_EQ(first_diff, static_cast<std::size_t>(r_top / dr));
  EXPECT_GT(post.intensity[first_diff], flat.intensity[first_diff]);
  // Between the top and the base (layover) the post's lit face dominates.
  for (double r = r_top + dr; r < r_base - dr; r += dr) {
    const auto i = static_cast<std::size_t>(r / dr);
    EXPECT_EQ(post.truth_class[i], SampleClass::object) << r;
    EXPECT_EQ(post.truth_label[i], 11) << r;
  }
}

}  // namespace
}  // namespace sonarsynth
