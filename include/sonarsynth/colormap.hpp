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
/// black_brown_yellow: the founding paper (Gwon et al., URAI 2017, eq. 3) maps intensity to a
/// black-brown-yellow ramp; its equation is unavailable, so this is our documented version, a
/// piecewise-linear RGB ramp through the anchors
///   v = 0    -> (  0,   0, 0)  black
///   v = 0.5  -> (150,  75, 0)  brown
///   v = 1    -> (255, 255, 0)  yellow
/// Rec. 709 luminance 0.2126 R + 0.7152 G + 0.0722 B is linear in RGB and increases at each
/// anchor (0, 85.5, 236.6), so it is monotone in v.
/// Channels are rounded to nearest.
Rgb8 colormap(Colormap map, double v);

}  // namespace sonarsynth
