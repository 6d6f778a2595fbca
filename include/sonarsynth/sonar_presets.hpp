// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "sonarsynth/sonar.hpp"

namespace sonarsynth {

/// A named sonar configuration modelled on a class of real instruments. docs/sonar-presets.md
/// gives the source of every value (a real file's headers, a vendor page, or a stated
/// assumption). A preset sets the frequency, range, samples, horizontal and vertical beams, tilt
/// and pulse; the sound speed and the ping period keep SonarConfig's defaults (1500 m/s, 2 R / c).
struct SonarPreset {
  std::string_view name;        ///< as a scene file's `sonar.preset` names it: "klein-3900-445"
  std::string_view instrument;  ///< what it models, one line
  SonarConfig sonar;
  // The output gain (OutputScaling::gain_db) a preset may set later goes here; the scene reader
  // would apply it unless `output.gain_db` is given (docs/sonar-presets.md, "Gain").
};

/// Every preset, in the order of docs/sonar-presets.md.
const std::vector<SonarPreset>& sonar_presets();

/// The preset names, comma-separated, in that order: "seascan-hds-600, edgetech-4200-300, ...".
std::string sonar_preset_names();

/// The preset called `name`, or nullptr.
const SonarPreset* find_sonar_preset(std::string_view name);

/// The SonarConfig of the preset called `name`. Throws InputError naming `name` and listing the
/// valid names if there is none.
SonarConfig sonar_preset(std::string_view name);

}  // namespace sonarsynth
