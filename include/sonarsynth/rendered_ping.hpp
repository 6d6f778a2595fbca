// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <limits>
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
  static constexpr double kNoPosition = std::numeric_limits<double>::quiet_NaN();
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
  /// Horizontal distance of the sample's dominant contributor from the nadir, along the side's
  /// across-track direction truth_across_dir, m (float: within 2^-24 of the renderer's double,
  /// 6 um at 100 m); NaN where none. Its local-frame position is truth_ground_xy(i).
  std::vector<float> truth_ground_range_m;
  /// The side's nadir (local frame, m) and across-track unit vector (local frame) of the truth's
  /// ground ranges; NaN without truth.
  Eigen::Vector2d truth_nadir_xy_m = Eigen::Vector2d::Constant(kNoPosition);
  Eigen::Vector2d truth_across_dir = Eigen::Vector2d::Constant(kNoPosition);

  /// Local-frame ground position (x, y) of sample i's dominant contributor, m: NaN where none.
  Eigen::Vector2d truth_ground_xy(std::size_t i) const {
    return ground_position(truth_nadir_xy_m, truth_across_dir, truth_ground_range_m[i]);
  }
  /// truth_ground_xy of every sample into x_m and y_m (truth_ground_range_m.size() values each).
  void truth_ground_positions(double* x_m, double* y_m) const {
    for (std::size_t i = 0; i < truth_ground_range_m.size(); ++i) {
      const Eigen::Vector2d p = truth_ground_xy(i);
      x_m[i] = p.x();
      y_m[i] = p.y();
    }
  }
  /// nadir + range x direction, the one formula of every ground position (the same bits on
  /// every path).
  static Eigen::Vector2d ground_position(const Eigen::Vector2d& nadir_xy_m,
                                         const Eigen::Vector2d& across_dir, float ground_range_m) {
    const double r = ground_range_m;  // NaN stays NaN
    return {nadir_xy_m.x() + r * across_dir.x(), nadir_xy_m.y() + r * across_dir.y()};
  }
};

struct RenderedPing {
  PingPose pose;  ///< as given, with the noise key the Simulator assigned if it was unset
  SideOutput port;
  SideOutput starboard;
};

}  // namespace sonarsynth
