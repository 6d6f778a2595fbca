// SPDX-License-Identifier: MIT
#pragma once

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
/// A plain struct of vectors: clear() keeps the capacity, so one instance can be refilled for
/// every ping without allocating.
struct BeamProfile {
  double sensor_z_m = 0.0;          ///< sensor height, same datum as z_m, metres
  std::vector<double> y_m;          ///< node ground range from nadir, metres, >= 0, non-decreasing
  std::vector<double> z_m;          ///< node height, metres, NaN = no seabed
  std::vector<std::int32_t> label;  ///< per facet (size = nodes - 1): 0 seabed, > 0 object id
  std::vector<std::uint16_t> material;  ///< per facet (size = nodes - 1): material table index

  std::size_t nodes() const { return y_m.size(); }
  /// Empties the profile, keeping the allocated capacity.
  void clear() {
    y_m.clear();
    z_m.clear();
    label.clear();
    material.clear();
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
