// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "sonarsynth/beam_profile.hpp"
#include "sonarsynth/material.hpp"

namespace sonarsynth {

/// The unit roughness field of one object (docs/physics.md §1.11): a sum of kWaves cosines with
/// standard normal wave vectors and uniform phases keyed on the object id,
///
///   u(p) = sqrt(2 / M) sum_m cos(n_m . p / L + phi_m),
///
/// of unit variance and autocorrelation exp(-d^2 / (2 L^2)) over the ensemble of ids, frozen in
/// the local frame (the same at a point of the object in every ping).
class RoughnessWaves {
 public:
  static constexpr int kWaves = 24;
  explicit RoughnessWaves(std::int32_t object_id);
  /// u at the local point (x, y, z) for correlation length `length_m` (unit variance).
  double unit_height(double x_m, double y_m, double z_m, double length_m) const;

 private:
  std::array<double, kWaves> nx_{}, ny_{}, nz_{}, phase_{};
};

/// Reusable buffers of roughen_sections() (one per thread).
struct RoughnessScratch {
  std::vector<double> y, z, ry, rz, h;
  std::vector<std::uint16_t> mat, rmat;
  std::vector<std::uint32_t> start;
  std::vector<std::int32_t> label;
  std::vector<std::uint16_t> section_mat;
};

/// True if some material of the table has roughness (roughness_rms_m > 0).
bool any_rough_material(const MaterialTable& materials);

/// Roughens the closed sections first_section .. out.sections() - 1 of `out` (one object, id
/// `object_id`, in the plane through nadir_xy + y across_dir): facets of a rough material are
/// subdivided to at most a third of its correlation length and every node moves along its
/// outward normal (the mean of its facets' unit normals) by the mean of its facets' heights
/// roughness_rms_m u(p); nodes on smooth facets only stay where they are. Nothing happens when
/// no facet of these sections has a rough material.
void roughen_sections(BeamProfile& out, std::size_t first_section, std::int32_t object_id,
                      const Eigen::Vector2d& nadir_xy_m, const Eigen::Vector2d& across_dir,
                      const MaterialTable& materials, RoughnessScratch& scratch);

}  // namespace sonarsynth
