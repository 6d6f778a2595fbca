// SPDX-License-Identifier: MIT
// Validation of the simulation configuration.
#include "sonarsynth/simulation_config.hpp"

#include <cmath>
#include <string>

#include "sonarsynth/error.hpp"

namespace sonarsynth {

void QualityConfig::validate() const {
  profile.validate();
  if (gauss_points < 1 || gauss_points > 5) {
    throw InputError("quality: gauss_points = " + std::to_string(gauss_points) +
                     ". Violated constraint: 1 <= gauss_points <= 5");
  }
  if (along_track_planes != kAutoPlanes && (along_track_planes < 1 || along_track_planes > 64)) {
    throw InputError("quality: along_track_planes = " + std::to_string(along_track_planes) +
                     ". Violated constraint: 1 <= along_track_planes <= 64 (or auto)");
  }
  if (!(along_track_tolerance_db > 0.0) || !std::isfinite(along_track_tolerance_db)) {
    throw InputError(
        "quality: along_track_tolerance_db = " + std::to_string(along_track_tolerance_db) +
        ". Violated constraint: along_track_tolerance_db > 0");
  }
}

void SimulationConfig::validate() const {
  sonar.validate();
  quality.validate();
  if (!(physics.calibration_k > 0.0) || !std::isfinite(physics.calibration_k)) {
    throw InputError("physics: calibration_k = " + std::to_string(physics.calibration_k) +
                     ". Violated constraint: calibration_k > 0");
  }
  if (physics.absorption) physics.water.validate();
  if (!(noise.paper_uniform_half_width >= 0.0 && noise.paper_uniform_half_width <= 1.0)) {
    throw InputError(
        "noise: uniform_half_width = " + std::to_string(noise.paper_uniform_half_width) +
        ". Violated constraint: 0 <= uniform_half_width <= 1");
  }
  if (!std::isfinite(noise.snr_at_max_range_db)) {
    throw InputError("noise: snr_db is not finite");
  }
  if (!std::isnan(noise.paper_uniform_variance) &&
      !(noise.paper_uniform_variance >= 0.0 && noise.paper_uniform_variance <= 1.0 / 3.0)) {
    throw InputError(
        "noise: uniform_variance = " + std::to_string(noise.paper_uniform_variance) +
        ". Violated constraint: 0 <= uniform_variance <= 1/3 (u ~ U(0, sqrt(12 gamma)) <= 2)");
  }
  if (!(noise.freeze_cell_m >= 0.0)) {
    throw InputError("noise: freeze_cell_m = " + std::to_string(noise.freeze_cell_m) +
                     ". Violated constraint: freeze_cell_m >= 0");
  }
  if (!(output.max_value > 0.0)) {
    throw InputError("output: max_value = " + std::to_string(output.max_value) +
                     ". Violated constraint: max_value > 0");
  }
  if (output.detector_sub_samples < 1 || output.detector_sub_samples > 16) {
    throw InputError(
        "output: detector_sub_samples = " + std::to_string(output.detector_sub_samples) +
        ". Violated constraint: 1 <= detector_sub_samples <= 16");
  }
  if (!(output.seabed_median_dbfs < 0.0)) {
    throw InputError("output: seabed_median_dbfs = " + std::to_string(output.seabed_median_dbfs) +
                     ". Violated constraint: seabed_median_dbfs < 0");
  }
  sensor.validate();
}

}  // namespace sonarsynth
