// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sonarsynth/formats/io/sonar_format.hpp"
#include "sonarsynth/formats/jsf/convert.hpp"  // ConvertResult

namespace sonarsynth {

/// Every sonar format sonarsynth knows, in the order of formats/registry/sonar_formats.cpp (XTF
/// first): the one list that `simulate`, the run check, the output directory, the any-format
/// reader, `info`, `convert`, `mosaic`, `waterfall`, `match` and Python iterate.
std::span<const SonarFormat* const> sonar_formats();

/// The format named `name` (SonarFormat::name, any case), or nullptr.
const SonarFormat* find_sonar_format(std::string_view name);

/// The format named `name`; throws InputError naming `what` (e.g. "output.formats"), the value
/// and the known names otherwise.
const SonarFormat& sonar_format_named(std::string_view name, std::string_view what);

/// "xtf, jsf": the known names, for messages and help texts; with `capability` (e.g.
/// &SonarFormatCapabilities::read) only those of the formats that have it.
std::string sonar_format_names(bool SonarFormatCapabilities::*capability = nullptr);

/// By the extension of `path` (any case), or nullptr.
const SonarFormat* sonar_format_for_extension(const std::filesystem::path& path);

/// By content, not by name: the first format whose identify() accepts the file's first
/// SonarFormat::kIdentifyBytes bytes, or nullptr. Throws FormatError if the file cannot be opened.
const SonarFormat* identify_sonar_format(const std::filesystem::path& path);

/// Every extension of every format (".xtf", ".jsf"): the output directory's data files.
std::vector<std::string> sonar_format_extensions();

/// What `sonarsynth info` prints about `path` (docs/xtf.md, docs/jsf.md): the format is taken
/// from the content. Throws FormatError if no readable format claims the file or it cannot be
/// read.
SonarFileInfo sonar_file_info(const std::filesystem::path& path, std::size_t max_anomalies = 20);

/// Converts `in` into `out` (`sonarsynth convert`, docs/jsf.md §4, docs/conversion.md): the
/// input format from the content, the output format from `out`'s extension, the conversion from
/// the formats' SonarFormat::conversions (today XTF -> JSF and JSF -> XTF: jsf/convert.hpp says
/// what they carry). Throws InputError for an unknown output extension or an unsupported pair,
/// FormatError for unreadable input and when no ping is left to write (then no output file is
/// created).
ConvertResult convert_sonar_file(const std::filesystem::path& in, const std::filesystem::path& out,
                                 bool overwrite = false,
                                 AltitudeSource altitude_source = AltitudeSource::kHeader);

}  // namespace sonarsynth
