// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <vector>

#include "sonarsynth/survey.hpp"

/// The output of rendering one ping: samples and per-sample truth of both sides.
namespace sonarsynth {

/// What a sample's dominant contribution is.
enum class SampleClass : std::uint8_t {
  water_column,  ///< before the first seabed return: no return
  seabed,        ///< dominated by a facet with label 0
  object,        ///< dominated by a facet with label > 0
  shadow,        ///< no return; the range interval is occluded (hidden) seabed
  no_seabed,     ///< no return; holes (NaN), beyond the profile end
};

/// One side's output, samples ordered NEAR -> FAR.
struct SideOutput {
  std::vector<float> samples;   ///< output units (after TVG and quantisation)
  std::uint32_t saturated = 0;  ///< samples clamped at OutputScaling::max_value
  std::uint32_t invalid = 0;    ///< samples that overflowed to a non-finite value, written as 0
  /// The same samples without noise (same TVG, gain, clamping and rounding), NEAR -> FAR; empty
  /// unless SimulationConfig::clean_samples.
  std::vector<float> clean_samples;
  // Truth (empty unless SimulationConfig::truth).
  std::vector<SampleClass> truth_class;
  /// Object id of an object echo, 0 seabed; of a shadow sample what casts it (> 0 the object, 0
  /// seabed relief alone, docs/labels.md "Shadow attribution"); -1 none.
  std::vector<std::int32_t> truth_label;
  std::vector<float> truth_grazing_rad;  ///< NaN where no seabed contributes
  std::vector<double> truth_ground_x_m;  ///< local frame; NaN where none
  std::vector<double> truth_ground_y_m;
};

struct RenderedPing {
  PingPose pose;  ///< as given, with the noise key the Simulator assigned if it was unset
  SideOutput port;
  SideOutput starboard;
};

}  // namespace sonarsynth
