// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

namespace sonarsynth {

/// Shape of the vertical (across-track) beam pattern.
enum class VerticalBeamShape {
  uniform,          ///< b = 1 everywhere (beam pattern off)
  paper_sine_pair,  ///< two half-sine lobes meeting at the axis (Gwon et al. 2017, see below)
  gaussian,         ///< exp(-4 ln2 (off / width_3db)^2), docs/physics.md §1.3
  sinc,             ///< [sin(x)/x]^2, x = pi (W / lambda) sin(off), docs/physics.md §1.3
  table,            ///< one-way gain in dB vs off-axis angle, linear interpolation
};

/// Vertical one-way INTENSITY pattern b(off) of a side-scan transducer as a function of the
/// off-axis angle off = depression - axis_depression (radians, positive = below the beam axis,
/// towards nadir; the depression angle is measured downward from the horizontal in the beam
/// plane). b(0) = 1 for every analytic shape. The echo is weighted by the two-way pattern
/// b_tx b_rx = b^2 (same array transmits and receives).
///
/// paper_sine_pair: the founding paper (Gwon et al., URAI 2017) models the vertical beam "using a
/// pair of sine wave functions" without a formula, so this is our documented interpretation:
///   b(off) = sin(pi/2 (1 + off / w_up))  = cos(pi/2 off / w_up)   for -w_up <= off <= 0,
///   b(off) = cos(pi/2 off / w_down)                                for 0 <= off <= w_down,
///   b(off) = 0 outside the main lobe,
/// i.e. two half-period sine lobes (quarter-wave each side) of separate half-widths meeting with
/// value 1 at the axis; the one-way intensity b falls to 1/2 (-3 dB) at off = -2 w_up/3,
/// +2 w_down/3 (the two-way b^2 at -w_up/2, +w_down/2).
struct VerticalBeamPattern {
  VerticalBeamShape shape = VerticalBeamShape::uniform;
  /// paper_sine_pair: half-width above the axis (towards the horizontal), radians, (0, pi].
  double upper_half_width_rad = 25.0 * (3.14159265358979323846 / 180.0);  // 25 deg
  /// paper_sine_pair: half-width below the axis (towards nadir), radians, (0, pi].
  double lower_half_width_rad = 25.0 * (3.14159265358979323846 / 180.0);  // 25 deg
  /// gaussian: full width between the one-way -3 dB points, radians, (0, pi].
  double width_3db_rad =
      50.0 * (3.14159265358979323846 / 180.0);  // 50 deg (MB-System mbbackangle default)
  /// sinc: element height over wavelength W / lambda, dimensionless, > 0.
  double height_over_wavelength = 1.0;
  /// table: off-axis angles, radians (degrees only at I/O), strictly increasing, >= 2 entries.
  std::vector<double> table_off_axis_rad;
  /// table: one-way intensity gain at those angles, dB (0 = on-axis reference), finite. Outside
  /// the table the end values are held.
  std::vector<double> table_gain_db;

  /// Throws InputError naming the violated constraint.
  void validate() const;
  /// One-way intensity b(off), dimensionless, >= 0.
  double one_way(double off_axis_rad) const;
  /// Full width between the one-way -3 dB points (b = 1/2) either side of the axis, radians:
  /// width_3db_rad for gaussian; found numerically (to 1e-12 rad) for the others (for
  /// paper_sine_pair that is 2/3 of upper + lower half-widths). 0 when the pattern does not fall to
  /// -3 dB within 90 deg on both sides (uniform, a flat table): no width to state.
  double width_3db_full_rad() const;
  /// Two-way pattern b(off)^2.
  double two_way(double off_axis_rad) const {
    const double b = one_way(off_axis_rad);
    return b * b;
  }
};

/// Effective along-track beam width of a uniform line array of length `array_length_m` used for
/// transmit and receive (docs/physics.md §1.3):
///   beta_eff = integral over psi in [-pi/2, pi/2] of D(psi)^4 dpsi,
///   D(psi) = sinc(pi L sin(psi) / lambda) (one-way pressure), so D^4 = b_tx b_rx.
/// For L >> lambda this tends to 2 lambda / (3 L) (integral of sinc^4 = 2 pi / 3). Radians.
/// Computed by composite 5-point Gauss–Legendre with >= 16 panels per sidelobe. Throws InputError
/// unless array_length_m > 0 and wavelength_m > 0.
double beta_eff_uniform_line_array_rad(double array_length_m, double wavelength_m);

}  // namespace sonarsynth
