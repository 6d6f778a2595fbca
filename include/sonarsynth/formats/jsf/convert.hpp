// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "sonarsynth/bottom_track.hpp"

namespace sonarsynth {

/// The raw side-scan formats sonarsynth reads and writes.
enum class SonarFileFormat : std::uint8_t { kUnknown, kXtf, kJsf };
/// "XTF", "JSF", "unknown".
const char* sonar_file_format_name(SonarFileFormat format);
/// By content, not by name: an XTF file starts with FileFormat 0x7B, a JSF file with the
/// message start marker bytes 01 16. kUnknown for anything else (or a file too short to tell).
/// Throws FormatError if the file cannot be opened.
SonarFileFormat detect_sonar_file_format(const std::filesystem::path& path);
/// By the extension of a file to be written (".xtf" or ".jsf", any case); kUnknown otherwise.
SonarFileFormat sonar_file_format_from_extension(const std::filesystem::path& path);

struct ConvertResult {
  SonarFileFormat from = SonarFileFormat::kUnknown;
  SonarFileFormat to = SonarFileFormat::kUnknown;
  std::uint64_t pings = 0;             ///< pings written
  std::uint64_t attitude_records = 0;  ///< attitude packets/messages written
  std::uint64_t pings_skipped = 0;     ///< pings dropped (counted by reason in `dropped`)
  std::uint64_t reader_anomalies = 0;
  std::uint64_t pings_tracked_altitude = 0;  ///< altitude replaced by the tracked one
  std::vector<std::string> warnings;         ///< the first few drops and reader anomalies
  /// Pings dropped, by reason (docs/conversion.md, "Drops"); the counts add up to pings_skipped.
  std::map<std::string, std::uint64_t> dropped;
  /// Fields written as the output's "unknown" (or neutral 0), by rule (docs/conversion.md,
  /// "Repairs"); one ping may count under several rules.
  std::map<std::string, std::uint64_t> repaired;
};

/// Converts a side-scan file between XTF and JSF (docs/jsf.md §4): the input format is taken
/// from its content, the output format from `out`'s extension. Port and starboard samples,
/// ping times and numbers, sensor position, heading, pitch, roll, heave, altitude, depth,
/// speed, sound speed and slant range are carried; XTF attitude packets (type 3) and JSF
/// pitch/roll messages (2020) are converted into each other. Samples survive XTF -> JSF -> XTF
/// bit-exactly; positions to JSF's 1/600 000 degree. The output is written atomically.
/// `altitude_source` (docs/conversion.md): kHeader (default) copies the altitude as it is;
/// kAuto / kTrack write the altitude tracked from the first return where choose_altitude()
/// picks it (one more pass over the input), counted in pings_tracked_altitude.
/// Pings the output cannot hold are dropped and counted by reason; fields it can hold only as
/// "unknown" are written so and counted by rule (docs/conversion.md, "Drops and repairs").
/// Throws InputError for unsupported format pairs, FormatError for unreadable input and when
/// no ping is left to write (then no output file is created).
ConvertResult convert_sonar_file(const std::filesystem::path& in, const std::filesystem::path& out,
                                 bool overwrite = false,
                                 AltitudeSource altitude_source = AltitudeSource::kHeader);

}  // namespace sonarsynth
