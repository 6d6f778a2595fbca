// SPDX-License-Identifier: MIT
#include "sonarsynth/colormap.hpp"

#include <algorithm>
#include <cmath>

namespace sonarsynth {
namespace {
std::uint8_t channel(double v) {
  return static_cast<std::uint8_t>(std::clamp(std::floor(v + 0.5), 0.0, 255.0));
}
}  // namespace

Rgb8 colormap(Colormap map, double v) {
  if (std::isnan(v)) return {};
  v = std::clamp(v, 0.0, 1.0);
  if (map == Colormap::grey) {
    const std::uint8_t c = channel(255.0 * v);
    return {c, c, c};
  }
  // The founding paper's eq. (3) (colormap.hpp, docs/physics.md §1.9).
  if (v < 0.8)
    return {channel(255.0 * 1.25 * v), channel(255.0 * 0.7812 * v), channel(255.0 * 0.4975 * v)};
  return {channel(255.0), channel(255.0 * (1.883 * v - 0.883)),
          channel(255.0 * (-1.99 * v + 1.99))};
}

}  // namespace sonarsynth
