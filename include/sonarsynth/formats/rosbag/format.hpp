// SPDX-License-Identifier: MIT
#pragma once

#include "sonarsynth/formats/io/sonar_format.hpp"

namespace sonarsynth::rosbag {

/// The ROS 1 bag format (docs/rosbag.md): names, the reader (`info`, `waterfall`, `mosaic`), the
/// `simulate` writer and the XTF -> bag, bag -> XTF and bag -> JSF conversions (its `conversions`)
/// (formats/rosbag/format.cpp). formats/registry/sonar_formats.cpp lists it.
const SonarFormat& sonar_format();

}  // namespace sonarsynth::rosbag
