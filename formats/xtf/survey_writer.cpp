// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/xtf/survey_writer.hpp"

#include <cmath>
#include <cstdio>

#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace {

std::string format_g(double v, int digits) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

}  // namespace

xtf::SampleEncoding xtf_sample_encoding(const std::string& sample_format) {
  if (sample_format == "u16") return xtf::SampleEncoding::kUint16;
  if (sample_format == "u8") return xtf::SampleEncoding::kUint8;
  if (sample_format == "f32") return xtf::SampleEncoding::kFloat32;
  throw InputError("output: sample_format = '" + sample_format +
                   "'. Violated constraint: u16, u8 or f32");
}

xtf::WriterOptions xtf_writer_options(const Simulator& sim, xtf::SampleEncoding encoding,
                                      const std::string& scene_name,
                                      bool allow_more_than_8192_samples) {
  const SimulationConfig& c = sim.config();
  xtf::WriterOptions o;
  o.sample_encoding = encoding;
  o.allow_more_than_8192_samples = allow_more_than_8192_samples;
  o.frequency_khz = c.sonar.frequency_hz / 1e3;
  o.horizontal_beam_angle_rad = c.sonar.horizontal_beam_width_rad;
  o.tilt_angle_rad = c.sonar.tilt_rad;
  o.vertical_beam_width_rad = c.sonar.vertical_beam.width_3db_full_rad();
  const bool tvg = c.output.tvg != TvgLaw::none;
  o.processing_flags = tvg ? xtf::kProcessingTvg : std::uint16_t{0};
  // The TVG law and the gain first, so that the header's 64-character NoteString holds them in
  // full (at most 60 characters: alpha to 6 and the gain to 10 significant digits).
  std::string law = tvg ? "TVG 30logR+2aR a=" + format_g(sim.absorption_db_per_m(), 6) + " dB/m"
                        : std::string("no TVG");
  const std::string head =
      law + ", gain " + format_g(sim.gain_db(), 10) + " dB; sonarsynth scene '";
  const std::string tail =
      "', seed " + std::to_string(c.seed) + "; samples: " +
      (c.output.quantity == SampleQuantity::amplitude ? "amplitude (envelope)" : "intensity");
  constexpr std::size_t kNoteChars = 200;
  std::string name = scene_name;
  const std::size_t room = kNoteChars - head.size() - tail.size();
  if (name.size() > room) name = name.substr(0, room - 3) + "...";
  o.note = head + name + tail;
  return o;
}

SonarPing to_xtf_ping(const RenderedPing& ping, const GeoFrame& frame, const SonarConfig& sonar) {
  const PingPose& p = ping.pose;
  SonarPing x;
  x.time_utc = p.time_utc;
  x.ping_number = static_cast<std::uint32_t>(p.ping_in_line);
  x.sensor_position = frame.geodetic_from_local(p.sensor_xy_m, p.sensor_z_m);
  x.ship_position = frame.geodetic_from_local(p.reference_xy_m, 0.0);
  double heading = p.heading_rad + frame.convergence_rad(p.sensor_xy_m);  // grid -> true
  heading = std::fmod(heading, 2.0 * kPi);
  if (heading < 0) heading += 2.0 * kPi;
  x.heading_true_rad = heading;
  x.pitch_rad = p.pitch_rad;
  x.roll_rad = p.roll_rad;
  x.heave_m = p.heave_m;
  // No seabed under the sensor (off the grid, over a hole): altitude 0, the XTF convention for
  // "no bottom", never a made-up height.
  x.altitude_m = std::isfinite(p.altitude_m) && p.altitude_m > 0 ? p.altitude_m : 0.0;
  x.depth_m = std::max(0.0, -p.sensor_z_m);
  x.speed_m_s = p.speed_m_s;
  x.sound_speed_m_s = sonar.sound_speed_m_s;
  x.slant_range_m = sonar.max_range_m;
  x.port = ping.port.samples;
  x.starboard = ping.starboard.samples;
  return x;
}

}  // namespace sonarsynth
