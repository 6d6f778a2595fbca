// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>

namespace sonarsynth {

/// An 8-bit sRGB colour.
struct Rgb8 {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
  bool operator==(const Rgb8&) const = default;
};

enum class Colormap {
  grey,                ///< v -> (255 v, 255 v, 255 v)
  black_brown_yellow,  ///< the founding paper's display map (see colormap())
};

/// Colour of a display value v in [0, 1] (clamped; NaN -> black).
///
/// black_brown_yellow: the founding paper's map (Gwon et al., URAI 2017, eq. 3; docs/physics.md
/// §1.9), its coefficients as printed, channels in [0, 1] scaled by 255:
///   R = 1.25 v,    G = 0.7812 v,         B = 0.4975 v            for 0 <= v < 0.8,
///   R = 1,         G = 1.883 v - 0.883,  B = -1.99 v + 1.99      for 0.8 <= v <= 1:
/// black at 0, brown (1, 0.625, 0.398) at 0.8, yellow (1, 1, 0) at 1. (As printed, G steps down
/// by 0.0016 at 0.8, 0.4 of an 8-bit level.)
/// Channels are rounded to nearest.
Rgb8 colormap(Colormap map, double v);

}  // namespace sonarsynth
