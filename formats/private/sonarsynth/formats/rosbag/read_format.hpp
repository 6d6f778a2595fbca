// SPDX-License-Identifier: MIT
// The ROS 1 bag format's read functions (formats/rosbag/read_format.cpp), which its SonarFormat
// (formats/rosbag/format.cpp) lists.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>

#include "sonarsynth/formats/io/sonar_format.hpp"

namespace sonarsynth::rosbag {

/// True for a file starting with "#ROSBAG V" (the reader accepts version 2.0 only).
bool identify(std::span<const std::uint8_t> head);
std::unique_ptr<SideScanSource> open_reader(const std::filesystem::path& path);
SonarFileInfo file_info(const std::filesystem::path& path, std::size_t max_anomalies);

}  // namespace sonarsynth::rosbag
