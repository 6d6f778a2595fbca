// SPDX-License-Identifier: MIT
// The uniform-angle ray caster (a benchmark comparison method) converges to the flat-seabed
// closed form of docs/physics.md §3.2 as the ray count grows, and leaves near-range bins empty
// when rays are few (ray-count aliasing, §2.3).
#include "sonarsynth/ray_renderer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <string>
#include <utility>

#include "analytic/flat_seabed.hpp"
#include "render_side_test_util.hpp"
#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace {

using analytic::flat_seabed_F;
using test::kBeta;
using test::kMu;

// The Lambertian seabed of the render_side tests, uniform beam, no absorption.
SideParams flat_params(double dr, std::size_t samples) {
  return test::base_params(dr, samples);
}

BeamProfile flat_profile(double h_m, double y_max_m) {
  BeamProfile b;
  b.sensor_z_m = h_m;
  b.add_node(0.0, 0.0);
  b.add_node(y_max_m, 0.0);
  return b;
}

// Relative error of the energy in [r1, r2) summed over bins, versus the closed form.
double band_error(const SideEcho& e, double dr, double h, double r1, double r2) {
  const auto i1 = static_cast<std::size_t>(r1 / dr), i2 = static_cast<std::size_t>(r2 / dr);
  double got = 0.0;
  for (std::size_t i = i1; i < i2; ++i) got += e.intensity[i];
  const double want = kMu * kBeta / (h * h) *
                      (flat_seabed_F(static_cast<double>(i2) * dr, h) -
                       flat_seabed_F(static_cast<double>(i1) * dr, h));
  return std::abs(got - want) / want;
}

TEST(RayRenderer, TotalEnergyMatchesClosedForm) {
  const double h = 10.0, dr = 0.05;
  const SideParams p = flat_params(dr, 2000);
  SideEcho e;
  render_side_rays(flat_profile(h, 200.0), p, 100000, e);
  EXPECT_LT(band_error(e, dr, h, 0.0, 100.0), 2e-3);
}

TEST(RayRenderer, PerBandErrorShrinksAsRaysGrow) {
  const double h = 10.0, dr = 0.05;
  const SideParams p = flat_params(dr, 1500);
  SideEcho e;
  double previous = 1e9;
  for (const std::size_t rays : {2000u, 20000u, 200000u}) {
    render_side_rays(flat_profile(h, 100.0), p, rays, e);
    // 1 m bands from 12 m to 70 m: loose, it is a sampling method.
    double worst = 0.0;
    for (double r = 12.0; r < 70.0; r += 1.0)
      worst = std::max(worst, band_error(e, dr, h, r, r + 1.0));
    EXPECT_LT(worst, previous) << rays;
    previous = worst;
  }
  EXPECT_LT(previous, 0.05);
}

TEST(RayRenderer, FewRaysLeaveFarBinsEmpty) {
  const double h = 10.0, dr = 0.05;
  const SideParams p = flat_params(dr, 1500);
  SideEcho e;
  render_side_rays(flat_profile(h, 100.0), p, 1000, e);
  std::size_t empty = 0;
  for (std::size_t i = static_cast<std::size_t>(h / dr) + 1; i < p.samples; ++i)
    empty += e.intensity[i] == 0.0;
  EXPECT_GT(empty, 500u);
}

TEST(RayRenderer, NothingBeforeFirstReturnAndRejectsZeroRays) {
  const double h = 10.0, dr = 0.05;
  const SideParams p = flat_params(dr, 400);
  SideEcho e;
  render_side_rays(flat_profile(h, 30.0), p, 5000, e);
  for (std::size_t i = 0; i < static_cast<std::size_t>(h / dr); ++i) ASSERT_EQ(e.intensity[i], 0.0);
  EXPECT_THROW(render_side_rays(flat_profile(h, 30.0), p, 0, e), InputError);
}

TEST(RayRenderer, RejectsTheProfilesTheExactRendererRejects) {
  // Both renderers share one profile check: the same bad profiles fail both, naming the field.
  const SideParams p = flat_params(0.05, 400);
  SideEcho e;
  BeamProfile backwards = flat_profile(10.0, 30.0);
  backwards.y_m[0] = 40.0;  // y_m no longer non-decreasing (40, then 30)
  BeamProfile bad_material = flat_profile(10.0, 30.0);
  bad_material.material[0] = 7;  // one material in the table
  BeamProfile short_z = flat_profile(10.0, 30.0);
  short_z.z_m.pop_back();
  for (const auto& [profile, field] :
       {std::pair{&backwards, "y_m["}, {&bad_material, "material["}, {&short_z, "z_m.size()"}}) {
    for (const bool rays : {true, false}) {
      try {
        if (rays) {
          render_side_rays(*profile, p, 1000, e);
        } else {
          render_side(*profile, p, e);
        }
        ADD_FAILURE() << field << " accepted";
      } catch (const InputError& err) {
        EXPECT_NE(std::string(err.what()).find(field), std::string::npos) << err.what();
        EXPECT_NE(std::string(err.what()).find(rays ? "render_side_rays:" : "render_side:"),
                  std::string::npos)
            << err.what();
      }
    }
  }
}

}  // namespace
}  // namespace sonarsynth
