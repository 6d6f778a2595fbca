// SPDX-License-Identifier: MIT
#pragma once

#include "sonarsynth/formats/io/sonar_format.hpp"

namespace sonarsynth::mcap {

/// ROS 2 bags in MCAP (docs/robotics.md): a `simulate` output format, the output of `convert`
/// from XTF, and read (`info`, `waterfall`, `mosaic`, the MCAP -> XTF and MCAP -> JSF
/// conversions), the conversions in its `conversions` (formats/mcap/format.cpp).
/// formats/registry/sonar_formats.cpp lists it.
const SonarFormat& sonar_format();

}  // namespace sonarsynth::mcap
