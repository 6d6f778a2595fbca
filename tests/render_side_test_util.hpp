// SPDX-License-Identifier: MIT
// The Lambertian seabed, side parameters and plane profiles shared by the render_side tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "analytic/flat_seabed.hpp"
#include "sonarsynth/render_side.hpp"

namespace sonarsynth::test {

constexpr double kMu = 0.01;
constexpr double kBeta = 0.02;

// Closed-form flat-seabed energy in the slant-range interval [r1, r2], altitude h.
inline double flat_energy(double r1, double r2, double h, double mu = kMu, double beta = kBeta) {
  return analytic::flat_seabed_energy(r1, r2, h, mu, beta);
}

inline SideParams base_params(double dr, std::size_t samples) {
  SideParams p;
  p.sample_spacing_m = dr;
  p.samples = samples;
  p.beta_eff_rad = kBeta;
  p.vertical_beam.shape = VerticalBeamShape::uniform;
  p.materials = {Material{.name = "test"}};
  p.materials[0].lambert_mu = kMu;
  p.absorption_db_per_m = 0.0;
  p.spreading = true;
  p.calibration_k = 1.0;
  return p;
}

// Plane z = y tan(slope) (rising towards the side for slope > 0), sensor at z = h, nodes
// every dy from y = 0 to y_max.
inline BeamProfile plane_profile(double h, double slope_rad, double y_max, double dy) {
  BeamProfile p;
  p.sensor_z_m = h;
  const auto n = static_cast<std::size_t>(std::ceil(y_max / dy));
  for (std::size_t i = 0; i <= n; ++i) {
    const double y = std::min(y_max, static_cast<double>(i) * dy);
    p.add_node(y, y * std::tan(slope_rad));
  }
  return p;
}

// A flat seabed at z = 0 with a box of height box_h over [y_front, y_back] labelled `label`,
// sensor at z = h, nodes every dy to y_max.
inline BeamProfile box_profile(double h, double box_h, double y_front, double y_back, double y_max,
                               double dy, std::int32_t label = 7) {
  BeamProfile p;
  p.sensor_z_m = h;
  for (double y = 0.0; y < y_front - 1e-9; y += dy) p.add_node(y, 0.0);
  p.add_node(y_front, 0.0);
  p.add_node(y_front, box_h, label);
  p.add_node(y_back, box_h, label);
  p.add_node(y_back, 0.0, label);
  for (double y = y_back + dy; y <= y_max; y += dy) p.add_node(y, 0.0);
  return p;
}

}  // namespace sonarsynth::test
