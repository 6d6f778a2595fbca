// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>

#include "sonarsynth/beam_pattern.hpp"

namespace sonarsynth {

/// The side-scan sonar: what it transmits and how it samples (both sides identical).
struct SonarConfig {
  double frequency_hz = 400e3;             ///< centre frequency, Hz, > 0
  double max_range_m = 75.0;               ///< slant range of the last sample, metres, > 0
  std::size_t samples_per_channel = 4096;  ///< samples per side, [1, 65535]
  double sound_speed_m_s = 1500.0;         ///< c, m/s, [1300, 1700]
  /// Vertical (across-track) one-way intensity pattern, relative to the beam axis.
  VerticalBeamPattern vertical_beam = default_vertical_beam();
  /// Beam-axis depression below horizontal, radians: 20 deg (exactly rad_from_deg(20.0), the
  /// value a scene file's tilt_deg: 20 gives).
  double tilt_rad = 20.0 * (3.14159265358979323846 / 180.0);
  /// Horizontal (along-track) one-way -3 dB beam width of a Gaussian pattern, radians, (0, pi/2).
  double horizontal_beam_width_rad = 1.0 * (3.14159265358979323846 / 180.0);  // 1 deg
  enum class Pulse { kCw, kChirp };
  Pulse pulse = Pulse::kCw;
  /// CW pulse length tau, seconds, >= 0 (0 = one sample interval). Range resolution c tau / 2.
  double pulse_length_s = 0.0;
  /// Chirp bandwidth B, Hz, > 0 for kChirp. Range resolution after matched filter c / (2 B).
  double bandwidth_hz = 0.0;
  /// Time between pings, seconds; 0 = the two-way travel time to max range, 2 R / c.
  double ping_period_s = 0.0;

  static VerticalBeamPattern default_vertical_beam();
  /// Throws InputError naming the violated constraint.
  void validate() const;

  double sample_spacing_m() const { return max_range_m / static_cast<double>(samples_per_channel); }
  /// Pulse window c tau / 2 (or c / 2B) in metres; 0 = the sample bin itself.
  double pulse_window_m() const;
  /// Range resolution: the pulse window, or the sample spacing if that is larger.
  double range_resolution_m() const;
  double effective_ping_period_s() const;
  /// beta_eff = integral of the two-way horizontal pattern b^2(psi) d psi for the Gaussian
  /// one-way pattern exp(-4 ln2 psi^2 / W^2): W sqrt(pi / (8 ln 2)), radians.
  double beta_eff_rad() const;
  /// Along-track length of the array whose one-way -3 dB width is horizontal_beam_width_rad,
  /// 0.886 lambda / theta (a uniform line array), metres.
  double array_length_m() const;
  /// Two-way horizontal pattern b^2(psi) of the Gaussian one-way pattern.
  double horizontal_two_way(double psi_rad) const;
};

}  // namespace sonarsynth
