// SPDX-License-Identifier: MIT
#pragma once
// Internal parts of the simulation file reader (include/sonarsynth/formats/config/
// simulation_file.hpp), shared by simulation_file.cpp (the sections but the survey),
// simulation_survey.cpp (`survey` and its lines) and effective_config.cpp (effective.yaml).

#include <filesystem>
#include <set>
#include <string>
#include <string_view>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"
#include "sonarsynth/formats/config/yaml_fields.hpp"

namespace sonarsynth::simulation_file {

using yaml::Fields;

// Farthest a waypoint may be from the bathymetry grid's centre, metres per axis: beyond it the
// local coordinates leave the scene's UTM zone by far.
inline constexpr double kMaxWaypointOffsetM = 1e6;

// Keys of one section: its declared options (formats/config/option_table.cpp) and `extra`
// sub-sections.
std::set<std::string> keys_of(std::string_view section, std::set<std::string> extra = {});

/// Runs `fn`; an InputError it throws becomes the error of `f`'s key path.
template <class F>
void wrap(const Fields& f, F&& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    f.fail("", e.what());
  }
}

/// `survey` (docs/scene-format.md): start time, vehicle, disturbance and the lines, given in the
/// file or read from a vector file relative to `base_dir`; `path` names the file in messages.
void read_survey_section(const Fields& sv, const std::string& path,
                         const std::filesystem::path& base_dir, SimulationSetup& setup);

}  // namespace sonarsynth::simulation_file
