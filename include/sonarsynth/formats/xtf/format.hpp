// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <filesystem>

#include "sonarsynth/formats/io/sonar_format.hpp"

namespace sonarsynth::xtf {

/// The XTF format (docs/xtf.md): names, identification, reader, `simulate` writer, `info`
/// (formats/xtf/format.cpp). formats/registry/sonar_formats.cpp lists it.
const SonarFormat& sonar_format();

/// What `sonarsynth info` prints about the XTF file `path` (formats/xtf/info.cpp). Throws
/// FormatError if it is not a readable XTF file.
SonarFileInfo file_info(const std::filesystem::path& path, std::size_t max_anomalies);

}  // namespace sonarsynth::xtf
