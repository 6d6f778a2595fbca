// SPDX-License-Identifier: MIT
// The sonar presets. Every value's source (file header, vendor page or assumption) is in
// docs/sonar-presets.md, whose tables follow the order of this file.
#include "sonarsynth/sonar_presets.hpp"

#include "sonarsynth/error.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth {
namespace {

struct Values {
  double frequency_khz, range_m;
  std::size_t samples;
  double tilt_deg, horizontal_beam_deg, vertical_beam_deg;
  SonarConfig::Pulse pulse;
  double pulse_length_us;  ///< CW
  double bandwidth_khz;    ///< chirp
};

SonarConfig make(const Values& v) {
  SonarConfig s;  // sound speed and ping period: SonarConfig's defaults
  s.frequency_hz = v.frequency_khz * 1e3;
  s.max_range_m = v.range_m;
  s.samples_per_channel = v.samples;
  s.tilt_rad = rad_from_deg(v.tilt_deg);
  s.horizontal_beam_width_rad = rad_from_deg(v.horizontal_beam_deg);
  s.vertical_beam = VerticalBeamPattern{};
  s.vertical_beam.shape = VerticalBeamShape::gaussian;
  s.vertical_beam.width_3db_rad = rad_from_deg(v.vertical_beam_deg);
  s.pulse = v.pulse;
  s.pulse_length_s = v.pulse_length_us * 1e-6;
  s.bandwidth_hz = v.bandwidth_khz * 1e3;
  return s;
}

constexpr auto kCw = SonarConfig::Pulse::kCw;
constexpr auto kChirp = SonarConfig::Pulse::kChirp;

std::vector<SonarPreset> make_presets() {
  // The Sea Scan pulse: 50 us, the CW pulse whose matched-filter response correlates
  // neighbouring samples as the real file's seabed does (docs/sonar-presets.md).
  const double seascan_pulse_us = 50.0;
  return {
      {"seascan-hds-600", "Marine Sonic Sea Scan HDS, 600 kHz, on an Iver2 AUV",
       make({600, 30, 1024, 15, 0.4, 50, kCw, seascan_pulse_us, 0})},
      {"edgetech-4200-300", "EdgeTech 4200 class towfish, 300 kHz channel (300/600 kHz set)",
       make({300, 230, 8192, 20, 0.54, 50, kChirp, 0, 25})},
      {"edgetech-4200-600", "EdgeTech 4200 class towfish, 600 kHz channel (300/600 kHz set)",
       make({600, 120, 8192, 20, 0.34, 50, kChirp, 0, 50})},
      {"klein-3900-445", "Klein 3900 class towfish, 445 kHz channel",
       make({445, 150, 4096, 20, 0.21, 40, kCw, 50, 0})},
      {"klein-3900-900", "Klein 3900 class towfish, 900 kHz channel",
       make({900, 50, 4096, 20, 0.08, 40, kCw, 25, 0})},
  };
}

}  // namespace

const std::vector<SonarPreset>& sonar_presets() {
  static const std::vector<SonarPreset> presets = make_presets();
  return presets;
}

std::string sonar_preset_names() {
  std::string names;
  for (const SonarPreset& p : sonar_presets()) {
    if (!names.empty()) names += ", ";
    names += p.name;
  }
  return names;
}

const SonarPreset* find_sonar_preset(std::string_view name) {
  for (const SonarPreset& p : sonar_presets()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

SonarConfig sonar_preset(std::string_view name) {
  if (const SonarPreset* p = find_sonar_preset(name)) return p->sonar;
  throw InputError("sonar preset '" + std::string(name) +
                   "' is unknown. Violated constraint: one of " + sonar_preset_names());
}

}  // namespace sonarsynth
