// SPDX-License-Identifier: MIT
// Closed forms of a circular section (a pipe across the beam plane, a sphere through its centre)
// above a flat seabed (docs/physics.md §2.1, §3.15), from the tangent lines of the circle alone:
// the analytic truth shared by the tests and the benchmark drivers.
#pragma once

#include <algorithm>
#include <cmath>

#include "flat_seabed.hpp"
#include "gauss_legendre.hpp"

namespace sonarsynth::analytic {

// A circle of radius a, centre (yc, zc), seen from the sensor S = (0, hs) (all in the beam
// plane), with the tangent lines from S: everything below is computed from this geometry alone.
struct CircleSection {
  double yc, zc, a, hs;
  double d() const { return std::hypot(yc, zc - hs); }
  double depression() const { return std::atan2(hs - zc, yc); }
  double half_angle() const { return std::asin(a / d()); }
  double nearest_range() const { return d() - a; }
  double tangent_range() const { return std::sqrt(d() * d() - a * a); }
  // Slant ranges where the tangent rays meet a flat seabed at z = 0: the shadow's ends.
  double shadow_start() const { return hs / std::sin(depression() + half_angle()); }
  // (Infinite when the shallower tangent does not descend: the shadow reaches the horizon.)
  double shadow_end() const {
    const double e = depression() - half_angle();
    return e > 0.0 ? hs / std::sin(e) : INFINITY;
  }
  // Lambert echo (mu cos^2 inc, r^-4 spreading, strip r beta, uniform beam) of the lit arc in
  // slant ranges [r1, r2]: psi is the angle at the centre from the direction of the sensor,
  // r^2 = d^2 + a^2 - 2 a d cos psi, cos(inc) = (d cos psi - a) / r, dl = a dpsi; both halves
  // of the arc (psi and -psi). Composite 5-point Gauss–Legendre, 64 panels: independent of
  // the renderer's polygon.
  double arc_energy(double r1, double r2, double mu, double beta) const {
    const double dd = d();
    const double psi_max = std::acos(a / dd);
    const auto psi_of = [&](double r) {
      const double c = (dd * dd + a * a - r * r) / (2.0 * a * dd);
      return std::clamp(std::acos(std::clamp(c, -1.0, 1.0)), 0.0, psi_max);
    };
    const double p0 = psi_of(r1), p1 = psi_of(r2);
    if (!(p1 > p0)) return 0.0;
    const double sum = gauss_legendre<5>(p0, p1, 64, [&](double psi) {
      const double r2sq = dd * dd + a * a - 2.0 * a * dd * std::cos(psi);
      const double c = dd * std::cos(psi) - a;
      return a * c * c / std::pow(r2sq, 2.5);
    });
    return 2.0 * mu * beta * sum;
  }

  /// Energy of bin [r1, r2] of the flat seabed z = 0 (hs below the sensor) outside the shadow
  /// [shadow_start, shadow_end], plus the lit arc's echo.
  double bin_energy(double r1, double r2, double mu, double beta) const {
    const double rs = shadow_start(), re = shadow_end();
    double e = r1 < rs ? flat_seabed_energy(r1, std::min(r2, rs), hs, mu, beta) : 0.0;
    if (r2 > re) e += flat_seabed_energy(std::max(r1, re), r2, hs, mu, beta);
    return e + arc_energy(r1, r2, mu, beta);
  }
};

}  // namespace sonarsynth::analytic
