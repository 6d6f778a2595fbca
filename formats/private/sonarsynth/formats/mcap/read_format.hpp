// SPDX-License-Identifier: MIT
// The MCAP format's read functions (formats/mcap/read_format.cpp), which its SonarFormat
// (formats/mcap/format.cpp) lists.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>

#include "sonarsynth/formats/io/sonar_format.hpp"

namespace sonarsynth::mcap {

/// True for a file starting with the MCAP magic (89 "MCAP0" CR LF).
bool identify(std::span<const std::uint8_t> head);
std::unique_ptr<SideScanSource> open_reader(const std::filesystem::path& path);
SonarFileInfo file_info(const std::filesystem::path& path, std::size_t max_anomalies);

}  // namespace sonarsynth::mcap
