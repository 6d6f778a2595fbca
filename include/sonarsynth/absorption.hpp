// SPDX-License-Identifier: MIT
#pragma once

namespace sonarsynth {

/// Sea-water properties for the absorption formula.
struct Seawater {
  double temperature_c = 10.0;  ///< temperature, deg C, [-2, 40]
  double salinity_psu = 35.0;   ///< practical salinity, psu, [0, 45]
  double depth_m = 20.0;        ///< depth below the surface, metres, [0, 12000]
  double ph = 8.0;              ///< pH, [6, 9]

  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// One-way absorption coefficient of sea water, dB per metre, by Francois & Garrison,
/// JASA 72(3):896-907 and 72(6):1879-1890 (1982) (boric acid + MgSO4 relaxation + pure water;
/// coefficients as in docs/physics.md §1.2). frequency_hz > 0 (formula fitted for
/// 0.4 kHz .. 1 MHz). Throws InputError on invalid input.
double francois_garrison_db_per_m(double frequency_hz, const Seawater& water);

}  // namespace sonarsynth
