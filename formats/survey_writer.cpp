// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/survey_writer.hpp"

#include <cmath>

#include "sonarsynth/error.hpp"

namespace sonarsynth {

xtf::SonarPing to_xtf_ping(const RenderedPing& ping, const GeoFrame& frame,
                           const SonarConfig& sonar) {
  const PingPose& p = ping.pose;
  xtf::SonarPing x;
  x.time_utc = p.time_utc;
  x.ping_number = static_cast<std::uint32_t>(p.ping_in_line);
  x.sensor_position = frame.geodetic_from_local(p.sensor_xy_m, p.sensor_z_m);
  x.ship_position = frame.geodetic_from_local(p.reference_xy_m, 0.0);
  double heading = p.heading_rad + frame.convergence_rad(p.sensor_xy_m);  // grid -> true
  heading = std::fmod(heading, 2.0 * kPi);
  if (heading < 0) heading += 2.0 * kPi;
  x.heading_rad = heading;
  x.pitch_rad = p.pitch_rad;
  x.roll_rad = p.roll_rad;
  x.heave_m = p.heave_m;
  // No seabed under the sensor (off the grid, over a hole): altitude 0, the XTF convention for
  // "no bottom", never a made-up height.
  x.altitude_m = std::isfinite(p.altitude_m) && p.altitude_m > 0 ? p.altitude_m : 0.0;
  x.depth_m = std::max(0.0, -p.sensor_z_m);
  x.speed_mps = p.speed_m_s;
  x.sound_speed_mps = sonar.sound_speed_m_s;
  x.slant_range_m = sonar.max_range_m;
  x.port = ping.port.samples;
  x.starboard = ping.starboard.samples;
  return x;
}

XtfSurveyWriter::XtfSurveyWriter(std::filesystem::path dir, std::vector<std::string> line_names,
                                 const GeoFrame& frame, const SonarConfig& sonar,
                                 xtf::WriterOptions options)
    : dir_(std::move(dir)),
      names_(std::move(line_names)),
      frame_(frame),
      sonar_(sonar),
      options_(std::move(options)) {
  options_.validate();
}

void XtfSurveyWriter::begin_line(std::size_t line) {
  const std::string name = line < names_.size() ? names_[line] : "line" + std::to_string(line + 1);
  writer_ = std::make_unique<xtf::Writer>(dir_ / (name + ".xtf"), options_);
}

void XtfSurveyWriter::ping(const RenderedPing& p) {
  if (!writer_) throw Error("xtf survey writer: ping outside a line");
  writer_->write_ping(to_xtf_ping(p, frame_, sonar_));
}

void XtfSurveyWriter::end_line(std::size_t /*line*/) {
  if (!writer_) return;
  writer_->close();
  clipped_ += writer_->clipped_samples();
  bytes_ += writer_->bytes_written();
  files_.push_back(writer_->path());
  writer_.reset();
}

}  // namespace sonarsynth
