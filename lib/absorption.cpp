// SPDX-License-Identifier: MIT
#include "sonarsynth/absorption.hpp"

#include <cmath>
#include <string>

#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace {
void check(const char* name, double v, double lo, double hi) {
  if (!(v >= lo && v <= hi)) {
    throw InputError("seawater: " + std::string(name) + " = " + std::to_string(v) +
                     ". Violated constraint: " + std::to_string(lo) + " <= " + name +
                     " <= " + std::to_string(hi));
  }
}
}  // namespace

void Seawater::validate() const {
  check("temperature_c", temperature_c, -2.0, 40.0);
  check("salinity_psu", salinity_psu, 0.0, 45.0);
  check("depth_m", depth_m, 0.0, 12000.0);
  check("ph", ph, 6.0, 9.0);
}

double francois_garrison_db_per_m(double frequency_hz, const Seawater& water) {
  water.validate();
  if (!(std::isfinite(frequency_hz) && frequency_hz > 0.0)) {
    throw InputError("absorption: frequency_hz = " + std::to_string(frequency_hz) +
                     ". Violated constraint: frequency_hz > 0");
  }
  // Francois & Garrison (1982), JASA 72(3):896 and 72(6):1879; docs/physics.md §1.2.
  const double f = frequency_hz * 1e-3;  // kHz
  const double t = water.temperature_c;
  const double s = water.salinity_psu;
  const double z = water.depth_m;
  const double c = 1412.0 + 3.21 * t + 1.19 * s + 0.0167 * z;
  const double theta = t + 273.0;
  // Boric acid.
  const double a1 = 8.86 / c * std::pow(10.0, 0.78 * water.ph - 5.0);
  const double p1 = 1.0;
  const double f1 = 2.8 * std::sqrt(s / 35.0) * std::pow(10.0, 4.0 - 1245.0 / theta);
  // Magnesium sulphate.
  const double a2 = 21.44 * s / c * (1.0 + 0.025 * t);
  const double p2 = 1.0 - 1.37e-4 * z + 6.2e-9 * z * z;
  const double f2 = 8.17 * std::pow(10.0, 8.0 - 1990.0 / theta) / (1.0 + 0.0018 * (s - 35.0));
  // Pure water.
  const double a3 = t <= 20.0 ? 4.937e-4 - 2.59e-5 * t + 9.11e-7 * t * t - 1.50e-8 * t * t * t
                              : 3.964e-4 - 1.146e-5 * t + 1.45e-7 * t * t - 6.5e-10 * t * t * t;
  const double p3 = 1.0 - 3.83e-5 * z + 4.9e-10 * z * z;
  const double f_sq = f * f;
  const double alpha_db_per_km = a1 * p1 * f1 * f_sq / (f1 * f1 + f_sq) +
                                 a2 * p2 * f2 * f_sq / (f2 * f2 + f_sq) + a3 * p3 * f_sq;
  return alpha_db_per_km * 1e-3;
}

}  // namespace sonarsynth
