// SPDX-License-Identifier: MIT
#pragma once

#include <filesystem>

#include "sonarsynth/bottom_track.hpp"
#include "sonarsynth/formats/io/sonar_format.hpp"
#include "sonarsynth/formats/jsf/convert.hpp"

namespace sonarsynth::rosbag {

/// The ROS 1 bag format (docs/rosbag.md): names, the reader (`info`, `waterfall`, `mosaic`), the
/// `simulate` writer and the XTF -> bag, bag -> XTF and bag -> JSF conversions
/// (formats/rosbag/format.cpp). formats/registry/sonar_formats.cpp lists it.
const SonarFormat& sonar_format();

/// Converts an XTF file into a ROS 1 bag (docs/rosbag.md, "Conversion"): every ping with its
/// samples (the XTF's sample type), time, number, position, heading, pitch, roll and sound speed;
/// XTF attitude packets as Imu messages. The bag's messages have no field for altitude, depth,
/// speed or heave: they are not carried, and `altitude_source` has no effect. Pings the bag
/// cannot hold are dropped and counted by reason. Throws FormatError for unreadable input and
/// when no ping is left to write (then no output file is created).
ConvertResult xtf_to_rosbag(const std::filesystem::path& in, const std::filesystem::path& out,
                            bool overwrite, AltitudeSource altitude_source);

/// Converts a ROS 1 bag into XTF (docs/rosbag.md, "Reading bags"): every ping (the port and
/// starboard images of one header.stamp) with its samples (u8 -> u8, float -> f32, other types
/// -> u16 clamped to 0..32767), time, number, sound speed, slant range, the position of the
/// NavSatFix and the heading, pitch and roll of the Imu at or before it; the other Imu messages
/// as attitude packets. Pings without a position are dropped (XTF's (0, 0) is "no fix").
/// `altitude_source` has no effect. Throws FormatError for unreadable input and when no ping is
/// left to write (then no output file is created).
ConvertResult rosbag_to_xtf(const std::filesystem::path& in, const std::filesystem::path& out,
                            bool overwrite, AltitudeSource altitude_source);
/// rosbag_to_xtf() into a temporary XTF file beside `out`, then xtf_to_jsf().
ConvertResult rosbag_to_jsf(const std::filesystem::path& in, const std::filesystem::path& out,
                            bool overwrite, AltitudeSource altitude_source);

}  // namespace sonarsynth::rosbag
