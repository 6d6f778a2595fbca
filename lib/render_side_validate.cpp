// SPDX-License-Identifier: MIT
// Input checks of the per-side renderer: its parameters and the beam-plane profile.
#include <cmath>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/render_side.hpp"

namespace sonarsynth {

void SideParams::validate() const {
  auto bad = [](const std::string& what) { throw InputError("side params: " + what); };
  if (!(std::isfinite(sample_spacing_m) && sample_spacing_m > 0.0)) {
    bad("sample_spacing_m = " + std::to_string(sample_spacing_m) +
        ". Violated constraint: sample_spacing_m > 0");
  }
  if (samples < 1 || samples > (std::size_t{1} << 24)) {
    bad("samples = " + std::to_string(samples) + ". Violated constraint: 1 <= samples <= 2^24");
  }
  if (!(std::isfinite(render_from_m) && render_from_m >= 0.0)) {
    bad("render_from_m = " + std::to_string(render_from_m) +
        ". Violated constraint: finite render_from_m >= 0");
  }
  if (gauss_points < 1 || gauss_points > 5) {
    bad("gauss_points = " + std::to_string(gauss_points) +
        ". Violated constraint: 1 <= gauss_points <= 5");
  }
  if (!(std::isfinite(beta_eff_rad) && beta_eff_rad > 0.0 && beta_eff_rad <= 3.14159265358979)) {
    bad("beta_eff_rad = " + std::to_string(beta_eff_rad) +
        ". Violated constraint: 0 < beta_eff_rad <= pi");
  }
  vertical_beam.validate();
  if (!(std::isfinite(beam_axis_depression_rad) &&
        std::abs(beam_axis_depression_rad) <= 3.141592653589793)) {
    // Beyond +-pi/2 (a tilted beam plus a large roll) the axis points past nadir or backwards
    // above the horizon; the off-axis angle stays well defined.
    bad("beam_axis_depression_rad = " + std::to_string(beam_axis_depression_rad) +
        ". Violated constraint: -pi <= beam_axis_depression_rad <= pi");
  }
  if (materials.empty()) bad("materials is empty. Violated constraint: materials.size() >= 1");
  for (const Material& m : materials) m.validate();
  if (!(std::isfinite(absorption_db_per_m) && absorption_db_per_m >= 0.0)) {
    bad("absorption_db_per_m = " + std::to_string(absorption_db_per_m) +
        ". Violated constraint: absorption_db_per_m >= 0");
  }
  if (!(std::isfinite(calibration_k) && calibration_k > 0.0)) {
    bad("calibration_k = " + std::to_string(calibration_k) +
        ". Violated constraint: calibration_k > 0");
  }
  if (!(std::isfinite(pulse_window_m) && pulse_window_m >= 0.0)) {
    bad("pulse_window_m = " + std::to_string(pulse_window_m) +
        ". Violated constraint: pulse_window_m >= 0");
  }
}

void validate_beam_profile(const BeamProfile& p, std::size_t n_materials, const char* who) {
  const auto fail = [who](const std::string& msg) {
    throw InputError(std::string(who) + ": " + msg);
  };
  const std::size_t n = p.y_m.size();
  if (p.z_m.size() != n) {
    fail("profile z_m.size() = " + std::to_string(p.z_m.size()) +
         ". Violated constraint: z_m.size() == y_m.size() = " + std::to_string(n));
  }
  const std::size_t facets = n == 0 ? 0 : n - 1;
  if (p.label.size() != facets || p.material.size() != facets) {
    fail("profile label.size() = " + std::to_string(p.label.size()) +
         ", material.size() = " + std::to_string(p.material.size()) +
         ". Violated constraint: label.size() == material.size() == nodes - 1 = " +
         std::to_string(facets));
  }
  if (!std::isfinite(p.sensor_z_m)) {
    fail("profile sensor_z_m = " + std::to_string(p.sensor_z_m) +
         ". Violated constraint: sensor_z_m finite");
  }
  double prev = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double y = p.y_m[i];
    if (!(std::isfinite(y) && y >= prev)) {
      fail("profile y_m[" + std::to_string(i) + "] = " + std::to_string(y) +
           ". Violated constraint: 0 <= y_m[i-1] <= y_m[i], finite");
    }
    prev = y;
  }
  for (std::size_t i = 0; i < facets; ++i) {
    if (p.material[i] >= n_materials) {
      fail("profile material[" + std::to_string(i) + "] = " + std::to_string(p.material[i]) +
           ". Violated constraint: material < materials.size() = " + std::to_string(n_materials));
    }
  }
  // Closed sections.
  const std::size_t ns = p.section_label.size();
  const std::size_t nn = p.section_y_m.size();
  if (p.section_material.size() != ns || p.section_z_m.size() != nn ||
      (ns == 0 ? !(p.section_start.empty() || p.section_start.size() == 1)
               : p.section_start.size() != ns + 1)) {
    fail("profile sections: section_label.size() = " + std::to_string(ns) +
         ", section_material.size() = " + std::to_string(p.section_material.size()) +
         ", section_start.size() = " + std::to_string(p.section_start.size()) +
         ", section_y_m.size() = " + std::to_string(nn) +
         ", section_z_m.size() = " + std::to_string(p.section_z_m.size()) +
         ". Violated constraint: one label, material per section, section_start = sections + 1, "
         "y and z of equal size");
  }
  for (std::size_t k = 0; k < ns; ++k) {
    const std::uint32_t a = p.section_start[k], b = p.section_start[k + 1];
    if (!(b >= a + 3 && b <= nn && (k > 0 || a == 0)) || (k + 1 == ns && b != nn)) {
      fail("profile section " + std::to_string(k) + ": nodes " + std::to_string(a) + ".." +
           std::to_string(b) + ". Violated constraint: >= 3 nodes, consecutive, covering all");
    }
    if (p.section_material[k] >= n_materials) {
      fail("profile section_material[" + std::to_string(k) +
           "] = " + std::to_string(p.section_material[k]) +
           ". Violated constraint: material < materials.size() = " + std::to_string(n_materials));
    }
  }
  if (!p.section_facet_material.empty() && p.section_facet_material.size() != nn) {
    fail("profile section_facet_material.size() = " +
         std::to_string(p.section_facet_material.size()) +
         ". Violated constraint: empty or one per section node (" + std::to_string(nn) + ")");
  }
  for (std::size_t i = 0; i < p.section_facet_material.size(); ++i) {
    if (p.section_facet_material[i] >= n_materials) {
      fail("profile section_facet_material[" + std::to_string(i) +
           "] = " + std::to_string(p.section_facet_material[i]) +
           ". Violated constraint: material < materials.size() = " + std::to_string(n_materials));
    }
  }
  for (std::size_t i = 0; i < nn; ++i) {
    if (!(std::isfinite(p.section_y_m[i]) && std::isfinite(p.section_z_m[i]) &&
          p.section_y_m[i] >= 0.0)) {
      fail("profile section node " + std::to_string(i) + " = (" + std::to_string(p.section_y_m[i]) +
           ", " + std::to_string(p.section_z_m[i]) + "). Violated constraint: finite, y >= 0");
    }
  }
}

}  // namespace sonarsynth
