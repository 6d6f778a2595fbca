// SPDX-License-Identifier: MIT
#include "sonarsynth/colormap.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace sonarsynth {
namespace {
std::uint8_t channel(double v) {
  return static_cast<std::uint8_t>(std::clamp(std::floor(v + 0.5), 0.0, 255.0));
}
struct Anchor {
  double v, r, g, b;
};
// Black -> brown -> yellow (documented in colormap.hpp).
constexpr Anchor kBby[] = {{0.0, 0.0, 0.0, 0.0}, {0.5, 150.0, 75.0, 0.0}, {1.0, 255.0, 255.0, 0.0}};
}  // namespace

Rgb8 colormap(Colormap map, double v) {
  if (std::isnan(v)) return {};
  v = std::clamp(v, 0.0, 1.0);
  if (map == Colormap::grey) {
    const std::uint8_t c = channel(255.0 * v);
    return {c, c, c};
  }
  std::size_t k = 1;
  while (k + 1 < std::size(kBby) && v > kBby[k].v) ++k;
  const Anchor& a = kBby[k - 1];
  const Anchor& b = kBby[k];
  const double s = (v - a.v) / (b.v - a.v);
  return {channel(a.r + s * (b.r - a.r)), channel(a.g + s * (b.g - a.g)),
          channel(a.b + s * (b.b - a.b))};
}

}  // namespace sonarsynth
