// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

#include "sonarsynth/beam_profile.hpp"
#include "sonarsynth/triangle_mesh.hpp"

namespace sonarsynth {

/// Reusable buffers of add_mesh_sections() (one per thread), and its counters.
struct MeshSliceScratch {
  struct Seg {
    double ya, za, yb, zb;      // A -> B in (y, z); the solid on its right
    std::uint64_t e_in, e_out;  // the mesh edges A and B lie on (vertex pair keys)
    std::uint16_t mat;
  };
  std::vector<std::uint32_t> tris;
  std::vector<Seg> segs;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> by_in;
  std::vector<std::int64_t> next;
  std::vector<std::uint8_t> has_pred, visited;
  std::vector<double> py, pz, cy, cz;
  std::vector<std::uint16_t> pm, cm;
  /// Open chains (a non-closed or non-manifold mesh) rendered as thin two-sided surfaces, and
  /// pieces dropped for having no extent; cumulative over calls.
  std::size_t open_chains = 0, dropped = 0;
};

/// Appends to `out` the sections of `mesh` (local frame) cut by the vertical plane through the
/// ray nadir_xy + y across_dir (unit): the triangles the plane crosses give oriented segments
/// (solid on the right, from the triangles' winding), chained through their shared edges into
/// closed polygons; an open chain becomes a thin two-sided surface. Cut at y = 0, collinear
/// nodes merged. Labelled `id`, with the triangles' materials. Never produces NaN.
void add_mesh_sections(const TriangleMesh& mesh, std::int32_t id, const Eigen::Vector2d& nadir_xy_m,
                       const Eigen::Vector2d& across_dir, BeamProfile& out,
                       MeshSliceScratch& scratch);

}  // namespace sonarsynth
