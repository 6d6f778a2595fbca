// SPDX-License-Identifier: MIT
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace sonarsynth {

/// The seabed seen by one side of one ping, in its beam plane (2-D across-track model, see
/// docs/physics.md §1.1 and §2.1).
///
/// Frame: y_m is the horizontal distance from the sensor's nadir, outward on the imaged side,
/// metres, >= 0; z_m is height (up positive), metres, in any datum shared with sensor_z_m. The
/// sensor sits at (y = 0, z = sensor_z_m). Nodes are ordered outward: y_m is non-decreasing
/// (two consecutive nodes with equal y form a vertical wall). z_m = NaN marks a node without
/// seabed (a hole in the DEM, outside the grid); every facet touching such a node is ignored.
/// Facet i joins node i and node i + 1 and carries label[i] (0 = seabed, > 0 = object id) and
/// material[i] (index into SideParams::materials).
///
/// Besides this heightfield, the profile holds closed sections: the cross-sections of objects
/// that do not rest on the seabed (free spans, moored and mid-water targets), each a polygon of
/// section nodes traversed clockwise in (y, z) (the solid on the right of every facet, so the
/// outward normal of facet A -> B is (-(z_B - z_A), y_B - y_A), as for the seabed). Section k holds
/// nodes section_start[k] .. section_start[k + 1] - 1; its last node joins its first. The
/// renderer occludes exactly between the heightfield and the sections (docs/physics.md §2.1).
///
/// A plain struct of vectors: clear() keeps the capacity, so one instance can be refilled for
/// every ping without allocating.
struct BeamProfile {
  double sensor_z_m = 0.0;          ///< sensor height, same datum as z_m, metres
  std::vector<double> y_m;          ///< node ground range from nadir, metres, >= 0, non-decreasing
  std::vector<double> z_m;          ///< node height, metres, NaN = no seabed
  std::vector<std::int32_t> label;  ///< per facet (size = nodes - 1): 0 seabed, > 0 object id
  std::vector<std::uint16_t> material;  ///< per facet (size = nodes - 1): material table index

  // Closed sections (see above); section_start is empty or has sections + 1 entries.
  std::vector<double> section_y_m;              ///< section node y, metres, finite, >= 0
  std::vector<double> section_z_m;              ///< section node z, metres, finite
  std::vector<std::uint32_t> section_start;     ///< first node of each section, then the total
  std::vector<std::int32_t> section_label;      ///< per section: object id (> 0)
  std::vector<std::uint16_t> section_material;  ///< per section: material table index
  /// Empty, or per section node: the material of its facet to the next node (mesh objects with
  /// per-face materials); when empty every facet of a section has section_material.
  std::vector<std::uint16_t> section_facet_material;

  std::size_t nodes() const { return y_m.size(); }
  std::size_t sections() const { return section_label.size(); }
  /// Empties the profile, keeping the allocated capacity.
  void clear() {
    y_m.clear();
    z_m.clear();
    label.clear();
    material.clear();
    section_y_m.clear();
    section_z_m.clear();
    section_start.clear();
    section_label.clear();
    section_material.clear();
    section_facet_material.clear();
  }
  /// Appends a closed section (nodes clockwise in (y, z)); at least 3 nodes.
  void add_section(const double* ys, const double* zs, std::size_t count, std::int32_t id,
                   std::uint16_t mat) {
    if (section_start.empty()) section_start.push_back(0);
    section_y_m.insert(section_y_m.end(), ys, ys + count);
    section_z_m.insert(section_z_m.end(), zs, zs + count);
    section_start.push_back(static_cast<std::uint32_t>(section_y_m.size()));
    section_label.push_back(id);
    section_material.push_back(mat);
    if (!section_facet_material.empty()) section_facet_material.resize(section_y_m.size(), mat);
  }
  /// Appends a closed section whose facets have their own materials (`mats[k]`: the facet from
  /// node k to the next); `mat` names the section (its first facet's material is typical).
  void add_section(const double* ys, const double* zs, const std::uint16_t* mats, std::size_t count,
                   std::int32_t id, std::uint16_t mat) {
    if (section_facet_material.empty()) {  // the sections so far: one material each
      for (std::size_t s = 0; s < sections(); ++s) {
        section_facet_material.resize(section_start[s + 1], section_material[s]);
      }
    }
    add_section(ys, zs, count, id, mat);
    section_facet_material.resize(section_y_m.size(), mat);
    std::copy(mats, mats + count,
              section_facet_material.end() - static_cast<std::ptrdiff_t>(count));
  }
  /// Material of the facet from section node k (in section s) to the next.
  std::uint16_t section_facet_mat(std::size_t s, std::size_t k) const {
    return section_facet_material.empty() ? section_material[s] : section_facet_material[k];
  }
  /// Facet index space of the renderer's truth: heightfield facets 0 .. nodes - 2, then section
  /// node k (its facet to the next node of its section) as nodes - 1 + k.
  /// End points of facet `i` in that space.
  void facet_ends(std::size_t i, double& ya, double& za, double& yb, double& zb) const {
    if (i + 1 < y_m.size()) {
      ya = y_m[i], za = z_m[i], yb = y_m[i + 1], zb = z_m[i + 1];
      return;
    }
    const std::size_t k = i - (y_m.empty() ? 0 : y_m.size() - 1);
    const std::size_t sec = section_of(k);
    const std::size_t next = k + 1 < section_start[sec + 1] ? k + 1 : section_start[sec];
    ya = section_y_m[k], za = section_z_m[k], yb = section_y_m[next], zb = section_z_m[next];
  }
  std::int32_t facet_label(std::size_t i) const {
    return i + 1 < y_m.size() ? label[i] : section_label[section_of(i - seabed_facets())];
  }
  std::uint16_t facet_material(std::size_t i) const {
    if (i + 1 < y_m.size()) return material[i];
    const std::size_t k = i - seabed_facets();
    return section_facet_mat(section_of(k), k);
  }
  std::size_t seabed_facets() const { return y_m.empty() ? 0 : y_m.size() - 1; }
  /// Section holding section node k.
  std::size_t section_of(std::size_t k) const {
    std::size_t s = 0;
    while (section_start[s + 1] <= k) ++s;
    return s;
  }
  /// Appends a node; for every node after the first also the facet that ends at it.
  void add_node(double node_y_m, double node_z_m, std::int32_t facet_label = 0,
                std::uint16_t facet_material = 0) {
    if (!y_m.empty()) {
      label.push_back(facet_label);
      material.push_back(facet_material);
    }
    y_m.push_back(node_y_m);
    z_m.push_back(node_z_m);
  }
};

}  // namespace sonarsynth
