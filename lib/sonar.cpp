// SPDX-License-Identifier: MIT
#include "sonarsynth/sonar.hpp"

#include <cmath>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth {
namespace {
void require(bool ok, const char* name, double value, const char* constraint) {
  if (!ok) {
    throw InputError(std::string("sonar: ") + name + " = " + std::to_string(value) +
                     ". Violated constraint: " + constraint);
  }
}
}  // namespace

VerticalBeamPattern SonarConfig::default_vertical_beam() {
  VerticalBeamPattern b;
  b.shape = VerticalBeamShape::gaussian;
  b.width_3db_rad = rad_from_deg(50.0);
  return b;
}

void SonarConfig::validate() const {
  require(frequency_hz > 0 && std::isfinite(frequency_hz), "frequency_hz", frequency_hz,
          "frequency_hz > 0");
  require(max_range_m > 0 && std::isfinite(max_range_m), "max_range_m", max_range_m,
          "max_range_m > 0");
  require(samples_per_channel >= 1 && samples_per_channel <= 65535, "samples_per_channel",
          static_cast<double>(samples_per_channel), "1 <= samples_per_channel <= 65535");
  require(sound_speed_m_s >= 1300 && sound_speed_m_s <= 1700, "sound_speed_m_s", sound_speed_m_s,
          "1300 <= sound_speed_m_s <= 1700");
  require(std::abs(tilt_rad) <= kPi / 2, "tilt", tilt_rad, "|tilt| <= 90 deg");
  require(horizontal_beam_width_rad > 0 && horizontal_beam_width_rad < kPi / 2,
          "horizontal_beam_width", horizontal_beam_width_rad, "0 < width < 90 deg");
  require(pulse_length_s >= 0 && pulse_length_s < 1.0, "pulse_length_s", pulse_length_s,
          "0 <= pulse_length_s < 1");
  if (pulse == Pulse::kChirp) {
    require(bandwidth_hz > 0 && std::isfinite(bandwidth_hz), "bandwidth_hz", bandwidth_hz,
            "bandwidth_hz > 0 for a chirp");
  }
  require(ping_period_s >= 0 && std::isfinite(ping_period_s), "ping_period_s", ping_period_s,
          "ping_period_s >= 0 (0 = from range)");
  vertical_beam.validate();
}

double SonarConfig::pulse_window_m() const {
  if (pulse == Pulse::kChirp) return sound_speed_m_s / (2.0 * bandwidth_hz);
  return 0.5 * sound_speed_m_s * pulse_length_s;
}

double SonarConfig::range_resolution_m() const {
  return std::max(pulse_window_m(), sample_spacing_m());
}

double SonarConfig::effective_ping_period_s() const {
  return ping_period_s > 0 ? ping_period_s : 2.0 * max_range_m / sound_speed_m_s;
}

double SonarConfig::beta_eff_rad() const {
  return horizontal_beam_width_rad * std::sqrt(kPi / (8.0 * std::log(2.0)));
}

double SonarConfig::array_length_m() const {
  return 0.886 * (sound_speed_m_s / frequency_hz) / horizontal_beam_width_rad;
}

double SonarConfig::horizontal_two_way(double psi_rad) const {
  const double x = psi_rad / horizontal_beam_width_rad;
  return std::exp(-8.0 * std::log(2.0) * x * x);
}

}  // namespace sonarsynth
