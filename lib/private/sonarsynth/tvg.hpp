// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <vector>

#include "sonarsynth/simulation_config.hpp"

namespace sonarsynth {

/// Time-varied gain G(r) in dB, applied to linear intensity as I * 10^(G/10).
struct Tvg {
  TvgLaw law = TvgLaw::spherical;
  double absorption_db_per_m = 0.0;  ///< one-way alpha, dB/m, >= 0 (use the simulator's alpha)
  /// k of the spherical law k log10 R, dB per decade of range, [0, 60]: 30 compensates seabed
  /// reverberation exactly (r^-4 spreading over an area growing as r).
  double spreading_db_per_decade = 30.0;
  /// Share of the two-way absorption the TVG compensates, [0, 1].
  double absorption_share = 1.0;
  double constant_db = 0.0;  ///< added gain, dB, finite
  double min_range_m = 0.1;  ///< r is clamped to >= this (log r -> -inf), metres, > 0

  /// Throws InputError naming the violated constraint.
  void validate() const;
  /// G(r), dB, for slant range r in metres.
  double gain_db(double slant_range_m) const;
};

/// Multiplies sample i (slant range first_range_m + i * spacing_m) by 10^(G(r)/10).
void apply_tvg(const Tvg& tvg, double first_range_m, double spacing_m,
               std::vector<double>& intensity);
/// The inverse of apply_tvg (divides by the same gain).
void remove_tvg(const Tvg& tvg, double first_range_m, double spacing_m,
                std::vector<double>& intensity);

/// Quantisation of linear intensity to an output sample range (e.g. XTF uint16 0..32767):
/// q = clamp(I * 10^(gain_db/10), 0, max_value), rounded to the nearest integer if
/// round_to_integer. Record gain_db in the output (XTF GainCode / notes) so it can be undone.
struct Quantizer {
  double gain_db = 0.0;          ///< gain applied before clipping, dB, finite
  double max_value = 32767.0;    ///< largest output value, > 0
  bool round_to_integer = true;  ///< integer sample formats; false for float32 output

  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// Quantises linear intensities (>= 0; NaN -> 0). If clipped_count is given it receives the
/// number of samples clipped at max_value.
std::vector<float> quantize(const std::vector<double>& intensity, const Quantizer& q,
                            std::size_t* clipped_count = nullptr);
/// Inverse of quantize (exact up to rounding and clipping): I = q * 10^(-gain_db/10).
std::vector<double> dequantize(const std::vector<float>& samples, const Quantizer& q);

}  // namespace sonarsynth
