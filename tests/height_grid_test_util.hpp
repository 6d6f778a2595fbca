// SPDX-License-Identifier: MIT
// Height grids sampled from analytic surfaces, shared by the grid, terrain and Simulator tests.
#pragma once

#include <functional>
#include <utility>
#include <vector>

#include "sonarsynth/height_grid.hpp"

namespace sonarsynth::test {

/// A grid of geometry `g` holding the surface f(x, y) at its nodes (default interpolation).
inline HeightGrid sampled_grid(const GridGeometry& g,
                               const std::function<double(double, double)>& f) {
  std::vector<float> z(g.size());
  for (std::size_t r = 0; r < g.rows; ++r) {
    for (std::size_t c = 0; c < g.cols; ++c) {
      z[r * g.cols + c] = static_cast<float>(
          f(g.x_of_col(static_cast<double>(c)), g.y_of_row(static_cast<double>(r))));
    }
  }
  return HeightGrid(g, std::move(z));
}

}  // namespace sonarsynth::test
