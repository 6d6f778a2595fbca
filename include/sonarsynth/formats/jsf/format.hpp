// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <filesystem>

#include "sonarsynth/formats/io/sonar_format.hpp"

namespace sonarsynth::jsf {

/// The JSF format (docs/jsf.md): names, identification, reader, `simulate` writer, `info`, the XTF
/// <-> JSF conversions (formats/jsf/format.cpp). formats/registry/sonar_formats.cpp lists it.
const SonarFormat& sonar_format();

/// What `sonarsynth info` prints about the JSF file `path` (formats/jsf/info.cpp). Throws
/// FormatError if it is not a readable JSF file.
SonarFileInfo file_info(const std::filesystem::path& path, std::size_t max_anomalies);

}  // namespace sonarsynth::jsf
