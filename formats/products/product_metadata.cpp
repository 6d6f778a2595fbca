// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/products/product_metadata.hpp"

#include <sstream>

#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth {
namespace {

const char* vertical_beam_name(VerticalBeamShape s) {
  switch (s) {
    case VerticalBeamShape::uniform:
      return "uniform";
    case VerticalBeamShape::paper_sine_pair:
      return "paper_sine_pair";
    case VerticalBeamShape::gaussian:
      return "gaussian";
    case VerticalBeamShape::sinc:
      return "sinc";
    case VerticalBeamShape::table:
      return "table";
  }
  return "unknown";
}

std::string vertical_beam(const VerticalBeamPattern& b) {
  std::string s = vertical_beam_name(b.shape);
  switch (b.shape) {
    case VerticalBeamShape::paper_sine_pair:
      return s + ", upper half-width " + metadata_number(deg_from_rad(b.upper_half_width_rad)) +
             " deg, lower half-width " + metadata_number(deg_from_rad(b.lower_half_width_rad)) +
             " deg";
    case VerticalBeamShape::gaussian:
      return s + ", -3 dB width " + metadata_number(deg_from_rad(b.width_3db_rad)) + " deg";
    case VerticalBeamShape::sinc:
      return s + ", W/lambda " + metadata_number(b.height_over_wavelength);
    case VerticalBeamShape::table:
      return s + ", " + std::to_string(b.table_off_axis_rad.size()) + " points";
    case VerticalBeamShape::uniform:
      break;
  }
  return s;
}

std::string pulse(const SonarConfig& s) {
  if (s.pulse == SonarConfig::Pulse::kChirp) {
    return "chirp, bandwidth " + metadata_number(s.bandwidth_hz) + " Hz";
  }
  return "cw, length " + metadata_number(s.pulse_length_s) + " s" +
         (s.pulse_length_s == 0.0 ? " (one sample interval)" : "");
}

}  // namespace

std::string metadata_number(double value) {
  std::ostringstream os;
  os.precision(15);  // what a double holds exactly in decimal: 20 deg from radians reads "20"
  os << value;
  return os.str();
}

MetadataItems run_metadata(const std::string& scene_name, const SimulationConfig& config,
                           double gain_db) {
  const SonarConfig& s = config.sonar;
  MetadataItems items = {
      {"SONARSYNTH_SCENE", scene_name},
      {"SONARSYNTH_SEED", std::to_string(config.seed)},
      {"SONARSYNTH_SONAR_FREQUENCY_HZ", metadata_number(s.frequency_hz)},
      {"SONARSYNTH_SONAR_RANGE_M", metadata_number(s.max_range_m)},
      {"SONARSYNTH_SONAR_SAMPLES_PER_SIDE", std::to_string(s.samples_per_channel)},
      {"SONARSYNTH_SONAR_SOUND_SPEED_M_S", metadata_number(s.sound_speed_m_s)},
      {"SONARSYNTH_SONAR_TILT_DEG", metadata_number(deg_from_rad(s.tilt_rad))},
      {"SONARSYNTH_SONAR_HORIZONTAL_BEAM_DEG",
       metadata_number(deg_from_rad(s.horizontal_beam_width_rad))},
      {"SONARSYNTH_SONAR_VERTICAL_BEAM", vertical_beam(s.vertical_beam)},
      {"SONARSYNTH_SONAR_PULSE", pulse(s)},
      {"SONARSYNTH_TVG", config.output.tvg == TvgLaw::spherical
                             ? metadata_number(config.output.tvg_spreading_db_per_decade) +
                                   " log10(R) + 2 x " +
                                   metadata_number(config.output.tvg_absorption_share) + " alpha R"
                             : "none"},
      {"SONARSYNTH_GAIN_DB", metadata_number(gain_db)},
      {"SONARSYNTH_SAMPLE_QUANTITY",
       config.output.quantity == SampleQuantity::amplitude ? "amplitude" : "intensity"},
      {"SONARSYNTH_DETECTOR", std::to_string(config.output.detector_sub_samples) + " looks, " +
                                  (config.output.detector == DetectorMode::max ? "max" : "mean")},
      {"SONARSYNTH_FULL_SCALE", metadata_number(config.output.max_value)},
  };
  if (config.output.normalise == OutputScaling::Normalise::per_ping_max) {
    items.emplace_back("SONARSYNTH_NORMALISATION",
                       "K = 1/Imax per ping: the largest noise-free sample of each ping (both "
                       "sides, after TVG) is the full scale, before the noise; "
                       "SONARSYNTH_GAIN_DB does not apply");
  }
  return items;
}

}  // namespace sonarsynth
