// SPDX-License-Identifier: MIT
// Analytic truths of docs/physics.md §3 for the per-side renderer (items 1-8, 13, stability).
#include "sonarsynth/render_side.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "analytic/flat_seabed.hpp"
#include "analytic/gauss_legendre.hpp"
#include "render_side_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/render_math.hpp"

namespace sonarsynth {
namespace {

constexpr double kPiT = 3.14159265358979323846;
using analytic::flat_seabed_F;
using test::base_params;
using test::box_profile;
using test::flat_energy;
using test::kBeta;
using test::kMu;
using test::plane_profile;

double rel_err(double got, double want) {
  return std::abs(got - want) / std::abs(want);
}

// Closed-form check of every bin of a flat seabed; returns the worst relative error.
double worst_flat_error(const SideEcho& e, const SideParams& p, double h) {
  double worst = 0.0;
  for (std::size_t i = 0; i < p.samples; ++i) {
    const double r1 = static_cast<double>(i) * p.sample_spacing_m;
    const double r2 = static_cast<double>(i + 1) * p.sample_spacing_m;
    const double want = flat_energy(r1, r2, h);
    if (want == 0.0) {
      EXPECT_EQ(e.intensity[i], 0.0) << "bin " << i;
    } else {
      worst = std::max(worst, rel_err(e.intensity[i], want));
    }
  }
  return worst;
}

TEST(RenderSide, FirstReturnFlatAndEarlierBinsExactlyZero) {
  const double h = 10.02, dr = 0.05;
  const SideParams p = base_params(dr, 400);
  SideEcho e;
  render_side(plane_profile(h, 0.0, 25.0, 0.1), p, e);
  const auto first = static_cast<std::size_t>(std::floor(h / dr));
  for (std::size_t i = 0; i < first; ++i) ASSERT_EQ(e.intensity[i], 0.0) << i;
  EXPECT_GT(e.intensity[first], 0.0);
}

TEST(RenderSide, FirstReturnOnRisingSlopeAtHCosS) {
  const double h = 10.0, dr = 0.02;
  for (const double slope_deg : {5.0, 10.0, 20.0}) {
    const double s = slope_deg * kPiT / 180.0;
    const SideParams p = base_params(dr, 700);
    SideEcho e;
    render_side(plane_profile(h, s, 13.0, 0.05), p, e);
    const double r_first = h * std::cos(s);
    const auto first = static_cast<std::size_t>(std::floor(r_first / dr));
    for (std::size_t i = 0; i < first; ++i) ASSERT_EQ(e.intensity[i], 0.0) << slope_deg << " " << i;
    EXPECT_GT(e.intensity[first], 0.0) << slope_deg;
  }
}

TEST(RenderSide, FlatSeabedClosedFormPerBin) {
  const double h = 10.01;  // not on a bin edge (the closed form cancels there)
  for (const double dr : {0.05, 0.0183}) {
    const SideParams p = base_params(dr, static_cast<std::size_t>(75.0 / dr));
    SideEcho e;
    render_side(plane_profile(h, 0.0, 80.0, 0.25), p, e);
    EXPECT_LT(worst_flat_error(e, p, h), 1e-6) << "dr " << dr;
  }
}

TEST(RenderSide, FlatSeabedClosedFormWithGaussPointsOneToFive) {
  const double h = 7.31;
  for (int g = 1; g <= 5; ++g) {
    SideParams p = base_params(0.05, 1200);
    p.gauss_points = g;
    SideEcho e;
    render_side(plane_profile(h, 0.0, 61.0, 0.5), p, e);
    // 1-point (midpoint) rule is O(h^2): looser; 2..5 points meet 1e-6 (docs/physics.md §3).
    EXPECT_LT(worst_flat_error(e, p, h), g == 1 ? 2e-3 : 1e-6) << "gauss points " << g;
  }
}

// Independent reference for a beam pattern and absorption (§3.2): the bin energy as an integral
// over the incidence angle phi, (mu beta / H^2) cos^3(phi) b^2(90 deg - phi - axis)
// exp(-kappa H / cos phi), by composite 10-point Gauss–Legendre written here.
double flat_energy_beam_absorption(double r1, double r2, double h, double axis_rad,
                                   double width_rad, double alpha_db_per_m) {
  r1 = std::max(r1, h);
  if (r2 <= r1) return 0.0;
  const double phi1 = std::acos(h / r1), phi2 = std::acos(h / r2);
  const double kappa = alpha_db_per_m * 2.0 * std::log(10.0) / 10.0;
  const double sum = analytic::gauss_legendre<10>(phi1, phi2, 4, [&](double phi) {
    const double off = (kPiT / 2 - phi) - axis_rad;
    const double b = std::exp(-4.0 * std::log(2.0) * (off / width_rad) * (off / width_rad));
    const double c = std::cos(phi);
    return c * c * c * b * b * std::exp(-kappa * h / c);
  });
  return kMu * kBeta / (h * h) * sum;
}

TEST(RenderSide, FlatSeabedWithGaussianBeamAndAbsorptionMatchesIncidenceIntegral) {
  const double h = 12.01, dr = 0.04, alpha = 0.096, axis = 20.0 * kPiT / 180,
               width = 50.0 * kPiT / 180;
  SideParams p = base_params(dr, 2000);
  p.vertical_beam.shape = VerticalBeamShape::gaussian;
  p.vertical_beam.width_3db_rad = width;
  p.beam_axis_depression_rad = axis;
  p.absorption_db_per_m = alpha;
  SideEcho e;
  render_side(plane_profile(h, 0.0, 85.0, 0.3), p, e);
  double worst = 0.0;
  for (std::size_t i = 0; i < p.samples; ++i) {
    const double r1 = static_cast<double>(i) * dr, r2 = static_cast<double>(i + 1) * dr;
    const double want = flat_energy_beam_absorption(r1, r2, h, axis, width, alpha);
    if (want == 0.0) {
      ASSERT_EQ(e.intensity[i], 0.0);
    } else {
      worst = std::max(worst, rel_err(e.intensity[i], want));
    }
  }
  EXPECT_LT(worst, 1e-6);
}

TEST(RenderSide, EnergyConservationIndependentOfBinSizeAndNodeSpacing) {
  const double h = 10.0, r_max = 100.0;
  const double want = kMu * kBeta / (h * h) * flat_seabed_F(r_max, h);
  for (const double dr : {0.02, 0.05, 0.25}) {
    for (const double dy : {0.05, 1.0}) {
      const SideParams p = base_params(dr, static_cast<std::size_t>(std::lround(r_max / dr)));
      SideEcho e;
      render_side(plane_profile(h, 0.0, 110.0, dy), p, e);
      double sum = 0.0;
      for (double v : e.intensity) sum += v;
      EXPECT_LT(rel_err(sum, want), 1e-8) << "dr " << dr << " dy " << dy;
    }
  }
}

TEST(RenderSide, PulseWindowSampleIsEnergyOfTrailingWindow) {
  const double h = 10.0, dr = 0.05;
  for (const double window : {0.05, 0.13, 0.15, 0.5, 0.037}) {
    SideParams p = base_params(dr, 1400);
    p.pulse_window_m = window;
    SideEcho e;
    render_side(plane_profile(h, 0.0, 75.0, 0.25), p, e);
    double worst = 0.0;
    for (std::size_t i = 0; i < p.samples; ++i) {
      const double r = static_cast<double>(i + 1) * dr;
      const double want = flat_energy(std::max(0.0, r - window), r, h);
      if (want == 0.0) {
        ASSERT_EQ(e.intensity[i], 0.0) << window << " " << i;
      } else {
        worst = std::max(worst, rel_err(e.intensity[i], want));
      }
    }
    EXPECT_LT(worst, 1e-6) << "window " << window;
  }
}

// Single-branch energy of a plane at perpendicular distance p over [r1, r2] (§3.5).
double branch_energy(double r1, double r2, double p) {
  return kMu * kBeta / (p * p) * (flat_seabed_F(r2, p) - flat_seabed_F(std::max(r1, p), p));
}

TEST(RenderSide, SlopedPlanesIncludingLayoverFold) {
  const double h = 10.01, dr = 0.05;
  for (const double slope_deg : {10.0, -10.0}) {
    const double s = slope_deg * kPiT / 180.0;
    const double p_dist = h * std::cos(s);
    const SideParams p = base_params(dr, 1200);
    SideEcho e;
    render_side(plane_profile(h, s, 65.0, 0.2), p, e);
    double worst = 0.0;
    std::size_t folded = 0;
    for (std::size_t i = 0; i < p.samples; ++i) {
      const double r1 = static_cast<double>(i) * dr, r2 = static_cast<double>(i + 1) * dr;
      double want;
      if (s > 0) {
        // Far branch (foot -> outward) everywhere >= p; near branch (nadir -> foot) folds onto
        // [p, H]: layover, those bins receive twice the single-branch value.
        want = (r2 > p_dist ? branch_energy(r1, r2, p_dist) : 0.0) +
               (r2 > p_dist && r1 < h ? branch_energy(r1, std::min(r2, h), p_dist) : 0.0);
        if (r2 <= h && r1 >= p_dist) {
          ++folded;
          EXPECT_NEAR(e.intensity[i], 2.0 * branch_energy(r1, r2, p_dist), 1e-6 * e.intensity[i]);
        }
      } else {
        // Falling away: only r >= H exists on this side.
        want = r2 > h ? kMu * kBeta / (p_dist * p_dist) *
                            (flat_seabed_F(r2, p_dist) - flat_seabed_F(std::max(r1, h), p_dist))
                      : 0.0;
      }
      if (want == 0.0) {
        ASSERT_EQ(e.intensity[i], 0.0) << slope_deg << " bin " << i;
      } else {
        worst = std::max(worst, rel_err(e.intensity[i], want));
      }
    }
    EXPECT_LT(worst, 1e-6) << "slope " << slope_deg;
    if (s > 0) {
      EXPECT_GE(folded, 2u);
    }
  }
}

TEST(RenderSide, ScaleInvarianceKMinusTwo) {
  const double k = 2.5;
  auto scaled = [&](double s) {
    BeamProfile b = box_profile(10.0 * s, 1.0 * s, 30.0 * s, 32.0 * s, 60.0 * s, 0.1 * s);
    SideParams p = base_params(0.05 * s, 1100);
    SideEcho e;
    render_side(b, p, e);
    return e.intensity;
  };
  const std::vector<double> e1 = scaled(1.0), ek = scaled(k);
  std::size_t nonzero = 0;
  const double peak = *std::max_element(e1.begin(), e1.end());
  for (std::size_t i = 0; i < e1.size(); ++i) {
    if (e1[i] == 0.0) {
      // A zero bin may differ only by a rounding-level sliver at a shadow edge.
      EXPECT_LE(ek[i] * k * k, 1e-12 * peak) << i;
      continue;
    }
    ++nonzero;
    EXPECT_NEAR(ek[i] * k * k, e1[i], 1e-9 * e1[i]) << i;
  }
  EXPECT_GT(nonzero, 500u);
}

TEST(RenderSide, PaperModelEqualsLambertWithMuEqualR) {
  SideParams lam = base_params(0.05, 1000);
  lam.materials[0].lambert_mu = 0.3;
  SideParams pap = lam;
  pap.backscatter = BackscatterModel::paper;
  pap.materials[0].lambert_mu = 0.9;  // ignored by the paper model
  pap.materials[0].paper_reflectivity = 0.3;
  SideEcho a, b;
  const BeamProfile prof = plane_profile(10.0, 0.0, 55.0, 0.25);
  render_side(prof, lam, a);
  render_side(prof, pap, b);
  for (std::size_t i = 0; i < a.intensity.size(); ++i) {
    ASSERT_DOUBLE_EQ(a.intensity[i], b.intensity[i]) << i;
  }
}

TEST(RenderSide, PaperModelMatchesEquiangularRaySum) {
  // Gwon's per-ray law evaluated by brute force: equiangular rays of width dtheta, each
  // contributing R beta dtheta cos(phi) / r^2, SUMMED per range bin (§1.5).
  const double h = 10.0, dr = 0.1, refl = 0.4;
  SideParams p = base_params(dr, 500);
  p.backscatter = BackscatterModel::paper;
  p.materials[0].paper_reflectivity = refl;
  SideEcho e;
  render_side(plane_profile(h, 0.0, 55.0, 0.5), p, e);
  std::vector<double> rays(p.samples, 0.0);
  const double theta_min = std::atan2(h, 60.0);
  const long n_rays = 1'000'000;
  const double dtheta = (kPiT / 2 - theta_min) / static_cast<double>(n_rays);
  for (long k = 0; k < n_rays; ++k) {
    const double theta = theta_min + (static_cast<double>(k) + 0.5) * dtheta;
    const double r = h / std::sin(theta);
    const double cos_phi = std::sin(theta);
    const auto bin = static_cast<std::size_t>(r / dr);
    if (bin < rays.size()) rays[bin] += refl * kBeta * dtheta * cos_phi / (r * r);
  }
  for (std::size_t i = static_cast<std::size_t>(12.0 / dr); i < p.samples; ++i) {
    EXPECT_NEAR(e.intensity[i], rays[i], 0.01 * rays[i]) << "bin " << i;
  }
}

TEST(RenderSide, TruthOnFlatSeabed) {
  const double h = 10.0, dr = 0.05;
  SideParams p = base_params(dr, 1000);
  p.truth = true;
  SideEcho e;
  render_side(plane_profile(h, 0.0, 45.0, 0.25), p, e);
  for (std::size_t i = 0; i < p.samples; ++i) {
    const double r1 = static_cast<double>(i) * dr, r2 = static_cast<double>(i + 1) * dr;
    if (r2 <= h) {
      EXPECT_EQ(e.truth_class[i], SampleClass::water_column) << i;
    } else if (r1 >= std::hypot(45.0, h)) {
      EXPECT_EQ(e.truth_class[i], SampleClass::no_seabed) << i;
    } else if (r1 > h) {
      ASSERT_EQ(e.truth_class[i], SampleClass::seabed) << i;
      EXPECT_EQ(e.truth_label[i], 0);
      // The dominant contributor lies within the bin: ground range and grazing angle.
      const double y = e.truth_ground_y_m[i];
      const double r = std::hypot(y, h);
      EXPECT_GE(r, r1 - 1e-9);
      EXPECT_LE(r, r2 + 1e-9);
      EXPECT_NEAR(e.truth_grazing_rad[i], std::asin(h / r), 1e-9);
      EXPECT_NEAR(e.truth_ground_z_m[i], 0.0, 1e-12);
    }
  }
}

// Grazing angle of the dominant contributor on facets of every slope (gentle ones, where the
// renderer uses a series, steep ones and walls facing the sensor): asin of cos(incidence) from
// the facet's normal and the ray to the truth point, computed here independently.
TEST(RenderSide, TruthGrazingOnFacetsOfEverySlope) {
  const double h = 10.0, dr = 0.02;
  SideParams p = base_params(dr, 3000);
  p.truth = true;
  BeamProfile prof;
  prof.sensor_z_m = h;
  const double slopes[] = {0.0, 0.04, -0.09, 0.3, -0.25, 0.08, 0.7, -0.02, 1.2, 0.0, -0.6, 0.15};
  double y = 0.0, z = 0.0;
  prof.add_node(y, z);
  for (int k = 0; k < 240; ++k) {
    const double s = slopes[k % 12];
    y += 0.25;
    z += 0.25 * std::tan(s);
    prof.add_node(y, z);
    if (k % 37 == 36) {  // a vertical step up, facing the sensor
      z += 0.3;
      prof.add_node(y, z);
    }
  }
  SideEcho e;
  render_side(prof, p, e);
  int checked = 0;
  for (std::size_t i = 0; i < p.samples; ++i) {
    if (e.truth_class[i] != SampleClass::seabed) continue;
    const double ty = e.truth_ground_y_m[i], tz = e.truth_ground_z_m[i];
    // The facet holding the point: strictly inside its y span, or a wall at its y.
    std::size_t f = prof.nodes();
    for (std::size_t k = 0; k + 1 < prof.nodes(); ++k) {
      const double y0 = prof.y_m[k], y1 = prof.y_m[k + 1];
      const bool wall = y0 == y1 && std::abs(ty - y0) < 1e-12 &&
                        tz > std::min(prof.z_m[k], prof.z_m[k + 1]) &&
                        tz < std::max(prof.z_m[k], prof.z_m[k + 1]);
      if (wall || (ty > y0 + 1e-9 && ty < y1 - 1e-9)) {
        f = k;
        break;
      }
    }
    if (f == prof.nodes()) continue;
    const double uy = prof.y_m[f + 1] - prof.y_m[f], uz = prof.z_m[f + 1] - prof.z_m[f];
    const double len = std::hypot(uy, uz);
    const double ny = -uz / len, nz = uy / len;
    const double my = ty, mz = tz - h, r = std::hypot(my, mz);
    const double want = std::asin(std::clamp(-(ny * my + nz * mz) / r, 0.0, 1.0));
    EXPECT_NEAR(e.truth_grazing_rad[i], want, 1e-12) << "sample " << i;
    ++checked;
  }
  EXPECT_GT(checked, 800);
}

void expect_finite_nonnegative(const SideEcho& e) {
  for (double v : e.intensity) {
    ASSERT_TRUE(std::isfinite(v));
    ASSERT_GE(v, 0.0);
  }
}

TEST(RenderSide, StabilityCases) {
  SideEcho e;
  // Very low altitude, with a node at y = 0 right under the sensor.
  {
    SideParams p = base_params(0.01, 5000);
    p.vertical_beam.shape = VerticalBeamShape::gaussian;
    p.absorption_db_per_m = 0.1;
    render_side(plane_profile(0.5, 0.0, 60.0, 0.05), p, e);
    expect_finite_nonnegative(e);
    for (std::size_t i = 0; i < 50; ++i) ASSERT_EQ(e.intensity[i], 0.0);  // r < 0.5 m
    EXPECT_GT(e.intensity[50], 0.0);
  }
  // 100 m altitude, 75 m of range: nothing in range, all zero, water column.
  {
    SideParams p = base_params(0.0183, 4096);
    p.truth = true;
    render_side(plane_profile(100.0, 0.0, 200.0, 1.0), p, e);
    for (std::size_t i = 0; i < p.samples; ++i) {
      ASSERT_EQ(e.intensity[i], 0.0);
      ASSERT_EQ(e.truth_class[i], SampleClass::water_column);
    }
  }
  // Entirely NaN profile: all zero, no seabed.
  {
    SideParams p = base_params(0.05, 100);
    p.truth = true;
    BeamProfile prof = plane_profile(10.0, 0.0, 50.0, 1.0);
    std::fill(prof.z_m.begin(), prof.z_m.end(), std::nan(""));
    render_side(prof, p, e);
    for (std::size_t i = 0; i < p.samples; ++i) {
      ASSERT_EQ(e.intensity[i], 0.0);
      ASSERT_EQ(e.truth_class[i], SampleClass::no_seabed);
    }
  }
  // Vertical walls (rising and falling), the sensor at the height of a wall top, 1 sample and
  // 65535 samples, empty and single-node profiles.
  {
    BeamProfile prof;
    prof.sensor_z_m = 2.0;
    prof.add_node(0.0, 0.0);
    prof.add_node(0.0, 1.0);  // wall at nadir
    prof.add_node(5.0, 1.0);
    prof.add_node(5.0, 2.0);  // wall up to the sensor height
    prof.add_node(8.0, 2.0);
    prof.add_node(8.0, -3.0);  // falling wall
    prof.add_node(40.0, -3.0);
    for (const std::size_t n : {std::size_t{1}, std::size_t{65535}}) {
      SideParams p = base_params(40.0 / static_cast<double>(n), n);
      p.truth = true;
      p.pulse_window_m = 0.3;
      render_side(prof, p, e);
      ASSERT_EQ(e.intensity.size(), n);
      expect_finite_nonnegative(e);
    }
    render_side(BeamProfile{}, base_params(0.05, 10), e);
    expect_finite_nonnegative(e);
    BeamProfile one;
    one.add_node(3.0, 0.0);
    render_side(one, base_params(0.05, 10), e);
    expect_finite_nonnegative(e);
  }
}

TEST(RenderSide, HoleGivesNoReturnAndDoesNotChangeHorizon) {
  const double h = 10.01, dr = 0.05;
  SideParams p = base_params(dr, 1000);
  p.truth = true;
  BeamProfile prof = plane_profile(h, 0.0, 50.0, 0.5);
  // Hole: nodes with 20 <= y <= 25 have no seabed.
  for (std::size_t i = 0; i < prof.nodes(); ++i) {
    if (prof.y_m[i] >= 20.0 && prof.y_m[i] <= 25.0) prof.z_m[i] = std::nan("");
  }
  SideEcho e;
  render_side(prof, p, e);
  for (std::size_t i = 0; i < p.samples; ++i) {
    const double r1 = static_cast<double>(i) * dr, r2 = static_cast<double>(i + 1) * dr;
    const double want = flat_energy(r1, r2, h);
    if (r2 <= std::hypot(19.5, h) || (r1 >= std::hypot(25.5, h) && r2 <= std::hypot(50.0, h))) {
      EXPECT_NEAR(e.intensity[i], want, 1e-6 * want) << i;
    } else if (r1 >= std::hypot(19.5, h) && r2 <= std::hypot(25.5, h)) {
      EXPECT_EQ(e.intensity[i], 0.0) << i;
      EXPECT_EQ(e.truth_class[i], SampleClass::no_seabed) << i;
    }
  }
}

TEST(RenderSide, ReusedEchoCarriesNoStateBetweenPings) {
  SideParams p = base_params(0.05, 900);
  p.truth = true;
  const BeamProfile a = box_profile(10.0, 1.0, 20.0, 22.0, 45.0, 0.2);
  const BeamProfile b = plane_profile(6.0, 0.1, 45.0, 0.3);
  SideEcho fresh, reused;
  render_side(a, p, fresh);
  render_side(b, p, reused);
  p.pulse_window_m = 0.12;
  render_side(b, p, reused);
  p.pulse_window_m = 0.0;
  render_side(a, p, reused);
  EXPECT_EQ(fresh.intensity, reused.intensity);
  EXPECT_EQ(fresh.truth_class, reused.truth_class);
  EXPECT_EQ(fresh.truth_label, reused.truth_label);
}

TEST(RenderSide, InvalidInputNamesTheConstraint) {
  SideParams p = base_params(0.05, 100);
  p.gauss_points = 0;
  SideEcho e;
  const BeamProfile prof = plane_profile(10.0, 0.0, 20.0, 1.0);
  try {
    render_side(prof, p, e);
    FAIL() << "expected InputError";
  } catch (const InputError& err) {
    EXPECT_NE(std::string(err.what())
                  .find("gauss_points = 0. Violated constraint: 1 <= "
                        "gauss_points <= 5"),
              std::string::npos)
        << err.what();
  }
  p.gauss_points = 2;
  BeamProfile bad = prof;
  bad.y_m[3] = 1.0;  // decreasing
  EXPECT_THROW(render_side(bad, p, e), InputError);
  bad = prof;
  bad.material[2] = 5;  // not in the table
  EXPECT_THROW(render_side(bad, p, e), InputError);
  bad = prof;
  bad.label.pop_back();
  EXPECT_THROW(render_side(bad, p, e), InputError);
  p.sample_spacing_m = 0.0;
  EXPECT_THROW(render_side(prof, p, e), InputError);
}

}  // namespace
}  // namespace sonarsynth
