// SPDX-License-Identifier: MIT
#pragma once
// What a raster product says about the run that made it: GDAL metadata items (domain "") that
// every writer of `simulate` copies into its files, next to the items each writer sets itself
// (SONARSYNTH_VERSION, SONARSYNTH_QUANTITY, SONARSYNTH_UNITS, band descriptions and units).

#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/simulator.hpp"

namespace sonarsynth {

using MetadataItems = std::vector<std::pair<std::string, std::string>>;

/// The run's identity and sonar: SONARSYNTH_SCENE, SONARSYNTH_SEED, SONARSYNTH_SONAR_FREQUENCY_HZ,
/// SONARSYNTH_SONAR_RANGE_M, SONARSYNTH_SONAR_SAMPLES_PER_SIDE, SONARSYNTH_SONAR_SOUND_SPEED_M_S,
/// SONARSYNTH_SONAR_TILT_DEG, SONARSYNTH_SONAR_HORIZONTAL_BEAM_DEG,
/// SONARSYNTH_SONAR_VERTICAL_BEAM, SONARSYNTH_SONAR_PULSE, SONARSYNTH_TVG, SONARSYNTH_GAIN_DB
/// (`gain_db`: the gain the run applied, automatic or not) and SONARSYNTH_FULL_SCALE (the
/// largest sample value). Numbers have 15 significant digits (metadata_number()).
MetadataItems run_metadata(const std::string& scene_name, const SimulationConfig& config,
                           double gain_db);

/// `value` with 15 significant digits, trailing zeros dropped ("400000", "0.25", "20" for
/// 20 degrees converted from radians).
std::string metadata_number(double value);

}  // namespace sonarsynth
