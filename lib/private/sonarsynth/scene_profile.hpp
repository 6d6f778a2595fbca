// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "sonarsynth/beam_profile.hpp"
#include "sonarsynth/scene.hpp"

namespace sonarsynth {

/// Reusable buffers of build_beam_profile() (one per thread).
struct ProfileScratch {
  std::vector<ProfilePoint> seabed;
  std::vector<std::uint32_t> candidates;
  struct Span {
    double s0, s1;
    std::uint32_t object;
  };
  std::vector<Span> spans;
  std::vector<double> s;
  std::vector<double> section_y, section_z, section_extent;
};

/// The seabed and objects along the horizontal ray nadir_xy + y * across_dir, 0 <= y <= max_y_m,
/// as the renderer's 2-D profile: the upper envelope of the bilinear seabed and of every object
/// resting on it (clearance_m = 0; sampled analytically, at their own resolution, with vertical
/// walls at their footprint edges), each facet labelled (0 seabed, else object id) and with its
/// material; and, for every object off the seabed (clearance_m > 0: free spans, moored targets),
/// its closed cross-section with the vertical plane through the ray (BeamProfile sections; a
/// convex polygon at the object's own resolution, cut at y = 0). Cost: the grid cells and
/// objects the ray crosses, not the scene size.
void build_beam_profile(const Scene& scene, const Eigen::Vector2d& nadir_xy_m,
                        const Eigen::Vector2d& across_dir, double max_y_m, double sensor_z_m,
                        const ProfileOptions& options, BeamProfile& out, ProfileScratch& scratch);

}  // namespace sonarsynth
