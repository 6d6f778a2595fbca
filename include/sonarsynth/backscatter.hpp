// SPDX-License-Identifier: MIT
#pragma once

#include <cmath>

#include "sonarsynth/material.hpp"

namespace sonarsynth {

/// Backscatter law applied per unit seabed area.
///
/// lambert: sigma_b = mu sin^2(g) = mu cos^2(phi), g grazing angle, phi incidence angle from the
///   local normal (Mackenzie 1961; docs/physics.md §1.5).
///
/// paper: the founding paper's per-ray intensity I = R K Phi cos(phi) (Gwon et al. 2017 after
///   Coiras et al., IEEE TIP 16(2), 2007), with equiangular rays of across-track width dtheta
///   that each carry 1/r^2 spreading and are SUMMED per range bin. One ray at range r
///   intercepts the seabed area dA = (r beta)(r dtheta) / sin(g) (along-track r beta times
///   across-track r dtheta / sin g). A per-area law sigma_b returns
///     sigma_b dA / r^4 = sigma_b beta dtheta / (r^2 sin g).
///   Equating with the per-ray law R beta dtheta cos(phi) / r^2 = R beta dtheta sin(g) / r^2 gives
///     sigma_b = R sin^2(g) = R cos^2(phi),
///   i.e. Lambert with mu = R (§1.5). The renderer therefore integrates both laws per
///   area with the coefficient mu (lambert) or R (paper); K is SideParams::calibration_k and Phi
///   is the incident intensity carried by the sonar equation (spreading, absorption, beam).
enum class BackscatterModel { lambert, paper };

/// The per-area coefficient in sigma_b = coefficient * cos^2(phi) of `m` under `model`.
inline double backscatter_coefficient(BackscatterModel model, const Material& m) {
  return model == BackscatterModel::lambert ? m.lambert_mu : m.paper_reflectivity;
}

/// sigma_b for a cosine of the incidence angle (<= 0: not illuminated, returns 0).
inline double backscatter_sigma(BackscatterModel model, const Material& m, double cos_incidence) {
  if (!(cos_incidence > 0.0)) return 0.0;
  return backscatter_coefficient(model, m) * cos_incidence * cos_incidence;
}

/// Near-normal (Kirchhoff, geometric-optics) backscatter of a surface whose unresolved slopes
/// are Gaussian with RMS s per direction (docs/physics.md §1.10 first return, §1.11 glints):
///
///   sigma(theta) = rho / (8 s^2 cos^4 theta) exp(-tan^2 theta / (2 s^2)),
///
/// theta the incidence angle from the mean surface's normal, rho the reflection coefficient.
/// The one definition of the lobe: the first bottom return (lib/sensor_effects.cpp) and object
/// glints (lib/private/sonarsynth/render_facet.hpp) both take it from here. Split into the peak
/// and the exponent so that a caller can fold the exponent into an exp() it already takes.
struct KirchhoffLobe {
  double peak = 0.0;     ///< rho / (8 s^2): sigma at normal incidence
  double inv_2s2 = 0.0;  ///< 1 / (2 s^2)
  /// Beyond this exponent sigma is below e^-40 of its peak: callers may stop there.
  static constexpr double kCutExponent = 40.0;

  static KirchhoffLobe make(double rho, double rms_slope) {
    const double s2 = rms_slope * rms_slope;
    return {rho / (8.0 * s2), 1.0 / (2.0 * s2)};
  }
  /// tan^2 theta / (2 s^2): sigma = peak sec^4 theta exp(-exponent).
  double exponent(double tan2) const { return tan2 * inv_2s2; }
  /// sigma from sec^2 theta = 1 / cos^2 theta (>= 1); 0 beyond kCutExponent.
  double sigma_of_sec2(double sec2) const {
    const double x = exponent(sec2 - 1.0);
    if (!(x < kCutExponent)) return 0.0;
    return peak * sec2 * sec2 * std::exp(-x);
  }
  /// sigma from cos theta (<= 0: not illuminated, returns 0).
  double sigma(double cos_theta) const {
    if (!(cos_theta > 0.0)) return 0.0;
    return sigma_of_sec2(1.0 / (cos_theta * cos_theta));
  }
};

/// The glint lobe of material `m` under `model` (peak 0 when it has none). rho is a physical
/// cross-section, on the scale of the Lambert mu; the paper model's R is that material's mu
/// rescaled (docs/physics.md §1.5), so under it the lobe takes the same factor R / mu: the
/// ratio of glint to diffuse return of a material is then the same under both models.
inline KirchhoffLobe specular_lobe(BackscatterModel model, const Material& m) {
  if (!(m.specular_rho > 0.0)) return {};
  KirchhoffLobe lobe = KirchhoffLobe::make(m.specular_rho, m.specular_rms_slope);
  if (model == BackscatterModel::paper) lobe.peak *= m.paper_reflectivity / m.lambert_mu;
  return lobe;
}

}  // namespace sonarsynth
