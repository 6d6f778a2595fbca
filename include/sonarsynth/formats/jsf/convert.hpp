// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "sonarsynth/bottom_track.hpp"
#include "sonarsynth/formats/io/convert_result.hpp"
#include "sonarsynth/formats/io/sonar_format.hpp"

namespace sonarsynth {

/// Converts an XTF file into JSF (xtf_to_jsf) or a JSF file into XTF (jsf_to_xtf): the JSF
/// format's two SonarFormat::conversions (docs/jsf.md §4); convert_sonar_file()
/// (sonar_formats.hpp) picks one from the format list. Port and starboard samples,
/// ping times and numbers, sensor position, heading, pitch, roll, heave, altitude, depth,
/// speed, sound speed and slant range are carried; XTF attitude packets (type 3) and JSF
/// pitch/roll messages (2020) are converted into each other. Samples survive XTF -> JSF -> XTF
/// bit-exactly; positions to JSF's 1/600 000 degree. The output is written atomically.
/// `altitude_source` (docs/conversion.md): kHeader (default) copies the altitude as it is;
/// kAuto / kTrack write the altitude tracked from the first return where choose_altitude()
/// picks it (one more pass over the input), counted in pings_tracked_altitude.
/// Pings the output cannot hold are dropped and counted by reason; fields it can hold only as
/// "unknown" are written so and counted by rule (docs/conversion.md, "Drops and repairs").
/// Throws FormatError for unreadable input (e.g. not of the input format) and when no ping is left
/// to write (then no output file is created).
ConvertResult xtf_to_jsf(const std::filesystem::path& in, const std::filesystem::path& out,
                         bool overwrite, AltitudeSource altitude_source);
ConvertResult jsf_to_xtf(const std::filesystem::path& in, const std::filesystem::path& out,
                         bool overwrite, AltitudeSource altitude_source);

}  // namespace sonarsynth
