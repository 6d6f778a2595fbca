// SPDX-License-Identifier: MIT
// Vertical beams that are not smooth (the paper's sine pair with its hard edges, a table): the
// renderer against the flat-seabed incidence integral of docs/physics.md §3.2, evaluated here
// with its own split at the beam's kinks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "analytic/gauss_legendre.hpp"
#include "sonarsynth/render_side.hpp"

namespace sonarsynth {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kMu = 0.01;
constexpr double kBeta = 0.02;

// The one-way paper sine pair written out from docs/physics.md §1.3 (not the library's).
double sine_pair(double off, double w_up, double w_down) {
  if (off <= -w_up || off >= w_down) return 0.0;
  return std::cos(0.5 * kPi * off / (off < 0.0 ? w_up : w_down));
}

// (mu beta / H^2) integral over the incidence angle phi of cos^3(phi) b2(90 deg - phi - axis),
// over the bin's incidence interval cut at every phi where the off-axis angle is a kink; each
// piece by composite 10-point Gauss–Legendre (8 panels).
double flat_energy_with_beam(double r1, double r2, double h, double axis_rad,
                             const std::function<double(double)>& b2,
                             const std::vector<double>& kinks_off_rad) {
  r1 = std::max(r1, h);
  if (r2 <= r1) return 0.0;
  const double phi1 = std::acos(h / r1), phi2 = std::acos(h / r2);
  std::vector<double> cuts = {phi1, phi2};
  for (const double k : kinks_off_rad) {
    const double phi = 0.5 * kPi - axis_rad - k;
    if (phi > phi1 && phi < phi2) cuts.push_back(phi);
  }
  std::sort(cuts.begin(), cuts.end());
  double sum = 0.0;
  for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
    sum += analytic::gauss_legendre<10>(cuts[c], cuts[c + 1], 8, [&](double phi) {
      const double cp = std::cos(phi);
      return cp * cp * cp * b2(0.5 * kPi - phi - axis_rad);
    });
  }
  return kMu * kBeta / (h * h) * sum;
}

SideParams flat_params(double dr, std::size_t samples, double axis_rad) {
  SideParams p;
  p.sample_spacing_m = dr;
  p.samples = samples;
  p.beta_eff_rad = kBeta;
  p.beam_axis_depression_rad = axis_rad;
  p.materials = {Material{.name = "test"}};
  p.materials[0].lambert_mu = kMu;
  return p;
}

BeamProfile flat_profile(double h, double y_max, double dy) {
  BeamProfile p;
  p.sensor_z_m = h;
  for (double y = 0.0; y < y_max + 0.5 * dy; y += dy) p.add_node(std::min(y, y_max), 0.0);
  return p;
}

// Worst relative error per bin; bins the reference leaves at 0 must be exactly 0.
double worst_relative_error(const SideEcho& e, const SideParams& p, double h,
                            const std::function<double(double)>& b2,
                            const std::vector<double>& kinks, std::size_t* lit = nullptr) {
  double worst = 0.0;
  std::size_t n_lit = 0;
  for (std::size_t i = 0; i < p.samples; ++i) {
    const double r1 = static_cast<double>(i) * p.sample_spacing_m;
    const double want = flat_energy_with_beam(r1, r1 + p.sample_spacing_m, h,
                                              p.beam_axis_depression_rad, b2, kinks);
    if (want == 0.0) {
      EXPECT_EQ(e.intensity[i], 0.0) << "bin " << i;
    } else {
      ++n_lit;
      worst = std::max(worst, std::abs(e.intensity[i] - want) / want);
    }
  }
  if (lit) *lit = n_lit;
  return worst;
}

// The paper beam's lower edge (axis + w_down) falls inside a bin at many altitudes: the bins
// on either side of it hold a small energy that an unsplit Gauss rule gets wrong by far more
// than 1e-6.
TEST(RenderSideBeam, PaperSinePairEdgesMatchIncidenceIntegral) {
  const double axis = 20.0 * kDeg, w_up = 25.0 * kDeg, w_down = 30.0 * kDeg, dr = 0.0183;
  for (const double h : {10.0, 10.013, 7.77, 14.2}) {
    SideParams p = flat_params(dr, 4096, axis);
    p.vertical_beam.shape = VerticalBeamShape::paper_sine_pair;
    p.vertical_beam.upper_half_width_rad = w_up;
    p.vertical_beam.lower_half_width_rad = w_down;
    SideEcho e;
    render_side(flat_profile(h, 75.0, 0.25), p, e);
    const auto b2 = [&](double off) {
      const double b = sine_pair(off, w_up, w_down);
      return b * b;
    };
    std::size_t lit = 0;
    EXPECT_LT(worst_relative_error(e, p, h, b2, {-w_up, 0.0, w_down}, &lit), 1e-6) << "h " << h;
    // The near-nadir bins beyond the lower edge are dark, the rest lit.
    const double r_edge = h / std::sin(axis + w_down);
    EXPECT_EQ(e.intensity[static_cast<std::size_t>(r_edge / dr) - 1], 0.0) << "h " << h;
    EXPECT_GT(lit, 4096u - static_cast<std::size_t>(r_edge / dr) - 2) << "h " << h;
  }
}

// A tilted axis puts the upper edge on the seabed too (axis - w_up > 0), and a coarse profile
// makes one facet span both edges.
TEST(RenderSideBeam, PaperSinePairBothEdgesOnOneFacet) {
  const double axis = 40.0 * kDeg, w_up = 15.0 * kDeg, w_down = 20.0 * kDeg, h = 9.5;
  SideParams p = flat_params(0.05, 1400, axis);
  p.vertical_beam.shape = VerticalBeamShape::paper_sine_pair;
  p.vertical_beam.upper_half_width_rad = w_up;
  p.vertical_beam.lower_half_width_rad = w_down;
  for (const double dy : {0.1, 70.0}) {
    SideEcho e;
    render_side(flat_profile(h, 70.0, dy), p, e);
    const auto b2 = [&](double off) {
      const double b = sine_pair(off, w_up, w_down);
      return b * b;
    };
    EXPECT_LT(worst_relative_error(e, p, h, b2, {-w_up, 0.0, w_down}), 1e-6) << "dy " << dy;
    // Beyond the upper edge (depression < axis - w_up) nothing returns.
    const double r_far = h / std::sin(axis - w_up);
    EXPECT_EQ(e.intensity[static_cast<std::size_t>(r_far / 0.05) + 1], 0.0);
  }
}

// A table beam (linear in dB between its angles) has a kink at every angle of the table.
TEST(RenderSideBeam, TableBeamKinksMatchIncidenceIntegral) {
  const double axis = 20.0 * kDeg, h = 11.3;
  SideParams p = flat_params(0.02, 3500, axis);
  p.vertical_beam.shape = VerticalBeamShape::table;
  const std::vector<double> angles = {-30 * kDeg, -12 * kDeg, 0.0, 9 * kDeg, 25 * kDeg};
  const std::vector<double> gains = {-20.0, -3.0, 0.0, -4.0, -25.0};
  p.vertical_beam.table_off_axis_rad = angles;
  p.vertical_beam.table_gain_db = gains;
  SideEcho e;
  render_side(flat_profile(h, 70.0, 0.3), p, e);
  const auto b2 = [&](double off) {
    double db = gains.front();
    if (off >= angles.back()) {
      db = gains.back();
    } else if (off > angles.front()) {
      std::size_t k = 1;
      while (angles[k] < off) ++k;
      db = gains[k - 1] +
           (off - angles[k - 1]) / (angles[k] - angles[k - 1]) * (gains[k] - gains[k - 1]);
    }
    const double b = std::pow(10.0, db / 10.0);
    return b * b;
  };
  EXPECT_LT(worst_relative_error(e, p, h, b2, angles), 1e-6);
}

}  // namespace
}  // namespace sonarsynth
