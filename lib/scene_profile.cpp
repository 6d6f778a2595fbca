// SPDX-License-Identifier: MIT
#include "sonarsynth/scene_profile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sonarsynth/error.hpp"
#include "sonarsynth/scene.hpp"

namespace sonarsynth {
namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Appends the closed section of object p with the vertical plane through start + s dir (the
// footprint crosses it over [a0, a1], unclipped): the upper boundary at increasing s, then the
// lower one back, at the sample positions of the envelope (ends, and for curved shapes points
// evenly spaced in the section's angle, s = mid - half cos(phi)); the part at s < 0 is cut off.
void add_object_section(const ObjectPrimitive& p, const Eigen::Vector2d& start,
                        const Eigen::Vector2d& dir, double a0, double a1, int segments,
                        BeamProfile& out, ProfileScratch& scratch) {
  const double c0 = std::max(a0, 0.0), c1 = a1;
  const double eps = 1e-9 * std::max(1.0, a1 - a0);
  if (!(c1 > c0) || !(a1 - a0 > 4.0 * eps)) return;
  auto& s = scratch.s;
  s.clear();
  s.push_back(c0);
  if (p.shape != ObjectShape::kBox) {
    const double mid = 0.5 * (a0 + a1), half = 0.5 * (a1 - a0);
    for (int k = 1; k < segments; ++k) {
      const double sk = mid - half * std::cos(kPi * k / segments);
      if (sk > c0 && sk < c1) s.push_back(sk);
    }
  }
  s.push_back(c1);
  // Vertical extent at each position, evaluated a hair inside the footprint so boundary
  // rounding cannot drop the object.
  auto& ext = scratch.section_extent;
  ext.clear();
  const std::size_t n = s.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector2d q = start + std::clamp(s[k], a0 + eps, a1 - eps) * dir;
    double zb = 0, zt = 0;
    if (!p.vertical_extent(q.x(), q.y(), zb, zt)) zb = zt = kNaN;
    // The rim of a curved section (evaluated a hair inside it): one node, not two.
    if (p.shape != ObjectShape::kBox && zt - zb <= 2e-4 * p.half_extent_m.z()) {
      zb = zt = 0.5 * (zb + zt);
    }
    ext.push_back(zt);
    ext.push_back(zb);
  }
  // A clockwise polygon: (s_k, top_k) for k up, then (s_k, bottom_k) for k down, without
  // repeated nodes (top = bottom at the footprint ends).
  auto& py = scratch.section_y;
  auto& pz = scratch.section_z;
  py.clear();
  pz.clear();
  const auto push = [&](double y, double z) {
    if (std::isnan(z)) return;
    if (!py.empty() && std::abs(py.back() - y) <= 1e-12 && std::abs(pz.back() - z) <= 1e-12) return;
    py.push_back(y);
    pz.push_back(z);
  };
  for (std::size_t k = 0; k < n; ++k) push(s[k], ext[2 * k]);
  for (std::size_t k = n; k-- > 0;) push(s[k], ext[2 * k + 1]);
  while (py.size() > 1 && std::abs(py.back() - py.front()) <= 1e-12 &&
         std::abs(pz.back() - pz.front()) <= 1e-12) {
    py.pop_back();
    pz.pop_back();
  }
  if (py.size() >= 3) out.add_section(py.data(), pz.data(), py.size(), p.id, p.material);
}

// The objects the ray from nadir_xy_m along across_dir crosses within max_y_m: meshes, and
// solids where asked, as closed sections of out; the other resting objects as spans of y that
// raise the height profile (scratch.spans).
void add_crossed_objects(const Scene& scene, const Eigen::Vector2d& nadir_xy_m,
                         const Eigen::Vector2d& across_dir, double max_y_m,
                         const ProfileOptions& options, BeamProfile& out, ProfileScratch& scratch) {
  scratch.spans.clear();
  scene.objects.candidates_along(nadir_xy_m, across_dir, max_y_m, scratch.candidates);
  const bool rough = !scratch.candidates.empty() && any_rough_material(scene.materials);
  for (std::uint32_t i : scratch.candidates) {
    double s0 = 0, s1 = 0;
    const ObjectPrimitive& prim = scene.objects.primitives()[i];
    if (prim.footprint_interval(nadir_xy_m, across_dir, s0, s1) && s1 > 0.0 && s0 < max_y_m &&
        s1 > s0) {
      // Meshes, and solids where asked, are closed sections; other resting objects raise the
      // height profile over their span.
      if (prim.shape != ObjectShape::kMesh && !(prim.clearance_m > 0.0) &&
          !options.solid_resting_objects) {
        scratch.spans.push_back({std::max(s0, 0.0), std::min(s1, max_y_m), i});
        continue;
      }
      const std::size_t first_section = out.sections();
      if (prim.shape == ObjectShape::kMesh) {  // its sections, cut by the plane
        if (prim.mesh)
          add_mesh_sections(*prim.mesh, prim.id, nadir_xy_m, across_dir, out, scratch.mesh);
      } else {  // a closed section
        add_object_section(prim, nadir_xy_m, across_dir, s0, s1, options.object_segments, out,
                           scratch);
      }
      if (rough) {
        roughen_sections(out, first_section, prim.id, nadir_xy_m, across_dir, scene.materials,
                         scratch.rough);
      }
    }
  }
}

// The sample positions of the upper envelope, sorted, in scratch.s: the seabed's, plus each
// object span's own (ends, and for curved sections points evenly spaced in the angle of the
// section's ellipse, s = mid - half cos(phi)).
void envelope_positions(const Scene& scene, const Eigen::Vector2d& nadir_xy_m,
                        const Eigen::Vector2d& across_dir, const ProfileOptions& options,
                        ProfileScratch& scratch) {
  auto& s = scratch.s;
  s.clear();
  for (const ProfilePoint& p : scratch.seabed) s.push_back(p.s_m);
  const auto& prims = scene.objects.primitives();
  for (const auto& span : scratch.spans) {
    s.push_back(span.s0);
    s.push_back(span.s1);
    if (prims[span.object].shape != ObjectShape::kBox) {
      // The unclipped section of a cylinder or ellipsoid along the ray.
      double a0 = 0, a1 = 0;
      prims[span.object].footprint_interval(nadir_xy_m, across_dir, a0, a1);
      const double mid = 0.5 * (a0 + a1), half = 0.5 * (a1 - a0);
      for (int k = 1; k < options.object_segments; ++k) {
        const double sk = mid - half * std::cos(kPi * k / options.object_segments);
        if (sk > span.s0 && sk < span.s1) s.push_back(sk);
      }
    }
  }
  std::sort(s.begin(), s.end());
}

// Height of the upper envelope (seabed and object spans) just after (side = +1) or just before
// (side = -1) position y, and which surface it belongs to (top_object; -1 = seabed).
[[gnu::always_inline]] inline double envelope_height(const Scene& scene,
                                                     const Eigen::Vector2d& nadir_xy_m,
                                                     const Eigen::Vector2d& across_dir,
                                                     const ProfileScratch& scratch, double y,
                                                     int side, std::int64_t& top_object) {
  const auto& prims = scene.objects.primitives();
  const Eigen::Vector2d p = nadir_xy_m + y * across_dir;
  double z = scene.bathymetry.height_m(p.x(), p.y());
  top_object = -1;
  for (const auto& span : scratch.spans) {
    const bool inside = side > 0 ? (y >= span.s0 && y < span.s1) : (y > span.s0 && y <= span.s1);
    if (!inside) continue;
    // Evaluate a hair inside the footprint so boundary rounding cannot drop the object.
    const double eps = 1e-9 * std::max(1.0, span.s1 - span.s0);
    const double yy = std::clamp(y, span.s0 + eps, span.s1 - eps);
    const Eigen::Vector2d q = nadir_xy_m + yy * across_dir;
    double zb = 0, zt = 0;
    if (prims[span.object].vertical_extent(q.x(), q.y(), zb, zt) && !(zt <= z)) {
      // A hole in the seabed under an object: the object still stands (its base was placed).
      z = zt;
      top_object = span.object;
    }
  }
  return z;
}

}  // namespace

void ProfileOptions::validate() const {
  if (grid_subdivisions < 1 || grid_subdivisions > 64) {
    throw InputError("profile: grid_subdivisions = " + std::to_string(grid_subdivisions) +
                     ". Violated constraint: 1 <= grid_subdivisions <= 64");
  }
  if (object_segments < 2 || object_segments > 256) {
    throw InputError("profile: object_segments = " + std::to_string(object_segments) +
                     ". Violated constraint: 2 <= object_segments <= 256");
  }
}

void build_beam_profile(const Scene& scene, const Eigen::Vector2d& nadir_xy_m,
                        const Eigen::Vector2d& across_dir, double max_y_m, double sensor_z_m,
                        const ProfileOptions& options, BeamProfile& out, ProfileScratch& scratch) {
  out.clear();
  out.sensor_z_m = sensor_z_m;
  const HeightGrid& grid = scene.bathymetry;
  const MaterialMap& mmap = scene.material_map;
  const bool uniform = mmap.uniform();
  const std::uint16_t default_material = mmap.default_material();
  auto seabed_material = [&](double y0, double y1) {
    if (uniform) return default_material;
    const Eigen::Vector2d p = nadir_xy_m + 0.5 * (y0 + y1) * across_dir;
    return mmap.material_at(p.x(), p.y());
  };

  grid.profile(nadir_xy_m, across_dir, max_y_m, options.grid_subdivisions, scratch.seabed);

  // Objects the ray crosses, as spans of y.
  add_crossed_objects(scene, nadir_xy_m, across_dir, max_y_m, options, out, scratch);

  if (scratch.spans.empty()) {  // Seabed only: the common case, no extra work.
    const auto& pts = scratch.seabed;
    for (std::size_t k = 0; k < pts.size(); ++k) {
      out.add_node(pts[k].s_m, pts[k].z_m, 0,
                   k == 0 ? default_material : seabed_material(pts[k - 1].s_m, pts[k].s_m));
    }
    return;
  }

  envelope_positions(scene, nadir_xy_m, across_dir, options, scratch);
  const auto& s = scratch.s;
  const auto& prims = scene.objects.primitives();

  auto envelope = [&](double y, int side, std::int64_t& top_object) {
    return envelope_height(scene, nadir_xy_m, across_dir, scratch, y, side, top_object);
  };

  const double min_gap = 1e-9 * std::max(1.0, max_y_m);
  double last_y = -1.0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const double y = s[k];
    if (k > 0 && y - last_y <= min_gap) continue;
    std::int64_t obj_before = -1, obj_after = -1;
    const double z_before = k == 0 ? kNaN : envelope(y, -1, obj_before);
    const double z_after = envelope(y, +1, obj_after);
    auto facet = [&](std::int64_t obj, double y0, double y1) {
      if (obj >= 0) {
        const auto& p = prims[static_cast<std::size_t>(obj)];
        return std::pair<std::int32_t, std::uint16_t>{p.id, p.material};
      }
      return std::pair<std::int32_t, std::uint16_t>{0, seabed_material(y0, y1)};
    };
    if (k > 0) {
      // Facet from the previous node to this one belongs to the surface just before y.
      const auto [lab, mat] = facet(obj_before, last_y, y);
      out.add_node(y, z_before, lab, mat);
      const bool wall = !(std::abs(z_after - z_before) <= 1e-9) && !std::isnan(z_after);
      if (wall) {
        const auto [wl, wm] = facet(z_after > z_before ? obj_after : obj_before, y, y);
        out.add_node(y, z_after, wl, wm);
      }
    } else {
      out.add_node(y, z_after, 0, default_material);
    }
    last_y = y;
  }
}

}  // namespace sonarsynth
