// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "sonarsynth/beam_profile.hpp"
#include "sonarsynth/mesh_slice.hpp"
#include "sonarsynth/object_roughness.hpp"
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
  MeshSliceScratch mesh;
  RoughnessScratch rough;
};

/// The seabed and objects along the horizontal ray nadir_xy + y * across_dir, 0 <= y <= max_y_m,
/// as the renderer's 2-D profile: the bilinear seabed as a height profile, and every object the
/// ray crosses as its closed cross-section with the vertical plane through the ray (BeamProfile
/// sections; a convex polygon at the object's own resolution, cut at y = 0). With
/// options.solid_resting_objects false, objects resting on the seabed (clearance_m = 0) enter
/// the height profile instead, as its upper envelope with the seabed (vertical walls at their
/// footprint edges). Facets are labelled (0 seabed, else object id) and carry their material.
/// Sections of objects of a rough material are roughened (roughen_sections, docs/physics.md §1.11).
/// Cost: the grid cells and objects the ray crosses, not the scene size.
void build_beam_profile(const Scene& scene, const Eigen::Vector2d& nadir_xy_m,
                        const Eigen::Vector2d& across_dir, double max_y_m, double sensor_z_m,
                        const ProfileOptions& options, BeamProfile& out, ProfileScratch& scratch);

}  // namespace sonarsynth
