// SPDX-License-Identifier: MIT
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "sonarsynth/scene.hpp"
#include "sonarsynth/simulator.hpp"
#include "sonarsynth/survey.hpp"

namespace sonarsynth {

/// Command-line overrides of common scene-file settings (GDAL-style: the file stays the
/// reference, the overrides are recorded in the effective configuration).
struct SimulationOverrides {
  std::optional<std::uint64_t> seed;
  std::optional<double> range_m;
  std::optional<std::size_t> samples;
  std::optional<unsigned> threads;
  /// "fast" (1 Gauss point, coarse objects), "default", "high" (4 grid subdivisions,
  /// 3 Gauss points, 5 along-track planes).
  std::optional<std::string> quality;
};

/// What `sonarsynth simulate` runs: the scene, the simulation settings and the survey.
struct SimulationSetup {
  Scene scene;
  SimulationConfig config;
  std::vector<SurveyLine> lines;
  VehicleConfig vehicle;
  UtcTime start_time{};
  std::string sample_format = "u16";  ///< XTF sample format: u16, u8 or f32
  /// The reference altitude for the global calibration (survey altitude, or depth above the
  /// mean seabed in constant-depth mode), metres.
  double reference_altitude_m = 10.0;
  Survey make_survey() const;
};

/// Loads a scene file with its survey, sonar, render, noise and output sections (format:
/// docs/scene-format.md) and applies the overrides. Throws InputError / FormatError naming the
/// file, the key and the bad value.
SimulationSetup load_simulation(const std::string& path, const SimulationOverrides& overrides = {});
/// As load_simulation(), from YAML text in memory: `name` stands for the file in messages,
/// relative file paths are relative to `base_dir`.
SimulationSetup load_simulation_from_string(const std::string& yaml_text, const std::string& name,
                                            const std::filesystem::path& base_dir,
                                            const SimulationOverrides& overrides = {});

/// Writes the effective configuration of a run: the scene file with absolute file paths, the
/// seed and the overrides applied, and the derived values (gain, absorption, EPSG...) under
/// `derived`, so that simulating it again reproduces the run exactly.
void write_effective_config(const std::string& scene_path, const SimulationOverrides& overrides,
                            const SimulationSetup& setup, const Simulator& sim,
                            const std::filesystem::path& out_path);

/// Parses "YYYY-MM-DDTHH:MM:SS[.ffffff]Z" (UTC); throws InputError naming `what`.
UtcTime parse_utc(const std::string& text, const std::string& what);
std::string format_utc(UtcTime t);

}  // namespace sonarsynth
