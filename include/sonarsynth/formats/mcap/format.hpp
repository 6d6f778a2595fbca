// SPDX-License-Identifier: MIT
#pragma once

#include <filesystem>

#include "sonarsynth/bottom_track.hpp"
#include "sonarsynth/formats/io/convert_result.hpp"
#include "sonarsynth/formats/io/sonar_format.hpp"

namespace sonarsynth::mcap {

/// ROS 2 bags in MCAP (docs/robotics.md): a `simulate` output format and the output of `convert`
/// from XTF (formats/mcap/format.cpp). formats/registry/sonar_formats.cpp lists it.
const SonarFormat& sonar_format();

/// Converts an XTF file into a ROS 2 bag (docs/robotics.md, "convert"): every ping the reader
/// gives, its samples in the XTF file's own sample type (16- or 8-bit unsigned integers as
/// uint16/uint8, anything else as float32). Pings the bag cannot hold are dropped and counted by
/// reason. Throws FormatError for unreadable input and when no ping is left (then no output file
/// is created). `altitude_source` is not used: the bag's messages carry no altitude.
ConvertResult xtf_to_mcap(const std::filesystem::path& in, const std::filesystem::path& out,
                          bool overwrite, AltitudeSource altitude_source);

}  // namespace sonarsynth::mcap
