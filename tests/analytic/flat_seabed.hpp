// SPDX-License-Identifier: MIT
// Closed forms of a flat seabed (docs/physics.md §3.2), written independently of the
// renderers: the analytic truth shared by the tests and the benchmark drivers.
#pragma once

#include <cmath>

namespace sonarsynth::analytic {

/// F(r) = s - s^3/3 with s = sqrt(1 - p^2 / r^2); 0 for r <= p (p: distance of the seabed
/// plane from the sensor).
inline double flat_seabed_F(double r, double p) {
  if (r <= p) return 0.0;
  const double s = std::sqrt(1.0 - (p * p) / (r * r));
  return s - s * s * s / 3.0;
}

/// Energy received from slant ranges [r1, r2] of a flat seabed h below the sensor, Lambert
/// coefficient mu, effective horizontal beam width beta (uniform vertical beam, no absorption):
/// mu beta / h^2 (F(r2) - F(r1)).
inline double flat_seabed_energy(double r1, double r2, double h, double mu, double beta) {
  return mu * beta / (h * h) * (flat_seabed_F(r2, h) - flat_seabed_F(r1, h));
}

}  // namespace sonarsynth::analytic
