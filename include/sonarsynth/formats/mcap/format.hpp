// SPDX-License-Identifier: MIT
#pragma once

#include <filesystem>

#include "sonarsynth/bottom_track.hpp"
#include "sonarsynth/formats/io/convert_result.hpp"
#include "sonarsynth/formats/io/sonar_format.hpp"

namespace sonarsynth::mcap {

/// ROS 2 bags in MCAP (docs/robotics.md): a `simulate` output format, the output of `convert`
/// from XTF, and read (`info`, `waterfall`, `mosaic`, the MCAP -> XTF and MCAP -> JSF
/// conversions) (formats/mcap/format.cpp). formats/registry/sonar_formats.cpp lists it.
const SonarFormat& sonar_format();

/// Converts an XTF file into a ROS 2 bag (docs/robotics.md, "convert"): every ping the reader
/// gives, its samples in the XTF file's own sample type (16- or 8-bit unsigned integers as
/// uint16/uint8, anything else as float32). Pings the bag cannot hold are dropped and counted by
/// reason. Throws FormatError for unreadable input and when no ping is left (then no output file
/// is created). `altitude_source` is not used: the bag's messages carry no altitude.
ConvertResult xtf_to_mcap(const std::filesystem::path& in, const std::filesystem::path& out,
                          bool overwrite, AltitudeSource altitude_source);

/// Converts a ROS 2 bag into XTF (docs/robotics.md, "Reading bags"): every ping (the port and
/// starboard RawSonarImage of one header.stamp) with its samples (uint8 -> u8, float -> f32,
/// other types -> u16 clamped to 0..32767), time, sound speed, slant range, the position of the
/// NavSatFix and the heading, pitch and roll of the Imu at or before it, the port image's
/// Message sequence as ping number; the other Imu messages as attitude packets. Pings without a
/// position are dropped (XTF's (0, 0) is "no fix"). `altitude_source` has no effect. Throws
/// FormatError for unreadable input and when no ping is left to write (then no output file is
/// created).
ConvertResult mcap_to_xtf(const std::filesystem::path& in, const std::filesystem::path& out,
                          bool overwrite, AltitudeSource altitude_source);
/// mcap_to_xtf() into a temporary XTF file beside `out`, then xtf_to_jsf().
ConvertResult mcap_to_jsf(const std::filesystem::path& in, const std::filesystem::path& out,
                          bool overwrite, AltitudeSource altitude_source);

}  // namespace sonarsynth::mcap
