// SPDX-License-Identifier: MIT
#pragma once

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

}  // namespace sonarsynth
