// SPDX-License-Identifier: MIT
#pragma once

#include <filesystem>

#include "sonarsynth/bottom_track.hpp"
#include "sonarsynth/formats/io/sonar_format.hpp"
#include "sonarsynth/formats/jsf/convert.hpp"

namespace sonarsynth::rosbag {

/// The ROS 1 bag format (docs/rosbag.md): names, the `simulate` writer and the XTF -> bag
/// conversion (formats/rosbag/format.cpp). Write only. formats/registry/sonar_formats.cpp lists
/// it.
const SonarFormat& sonar_format();

/// Converts an XTF file into a ROS 1 bag (docs/rosbag.md, "Conversion"): every ping with its
/// samples (the XTF's sample type), time, number, position, heading, pitch, roll and sound speed;
/// XTF attitude packets as Imu messages. The bag's messages have no field for altitude, depth,
/// speed or heave: they are not carried, and `altitude_source` has no effect. Pings the bag
/// cannot hold are dropped and counted by reason. Throws FormatError for unreadable input and
/// when no ping is left to write (then no output file is created).
ConvertResult xtf_to_rosbag(const std::filesystem::path& in, const std::filesystem::path& out,
                            bool overwrite, AltitudeSource altitude_source);

}  // namespace sonarsynth::rosbag
