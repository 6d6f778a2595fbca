// SPDX-License-Identifier: MIT
#include "sonarsynth/ray_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

// Depression angle of node (y, z) seen from the sensor at (0, hs), radians, in [-pi/2, pi/2].
double depression_rad(double y_m, double z_m, double hs_m) {
  return std::atan2(hs_m - z_m, y_m);
}

}  // namespace

void render_side_rays(const BeamProfile& profile, const SideParams& params, std::size_t rays,
                      SideEcho& out) {
  params.validate();
  if (rays == 0) throw InputError("rays = 0. Violated constraint: rays >= 1");
  validate_beam_profile(profile, params.materials.size(), "render_side_rays");
  const std::size_t n = profile.nodes();
  out.intensity.assign(params.samples, 0.0);
  out.clear_truth();
  if (n < 2) return;

  const double hs = profile.sensor_z_m;
  // Horizon in depression angle: h[i] = max over nodes j <= i of the depression is the wrong
  // way round; a node hides what lies behind it when its depression is SMALLER. A ray of
  // depression theta first meets the seabed at the first node whose depression <= theta, so keep
  // the running minimum of the node depressions (non-increasing) and binary-search it.
  std::vector<double> horizon(n);
  double run = kInf;
  double lo = kInf, hi = -kInf;
  for (std::size_t i = 0; i < n; ++i) {
    const double z = profile.z_m[i];
    if (z == z) {
      const double d = profile.y_m[i] > 0.0 ? depression_rad(profile.y_m[i], z, hs)
                                            : (z < hs ? 0.5 * kPi : -0.5 * kPi);
      run = std::min(run, d);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    horizon[i] = run;
  }
  if (!(lo <= hi)) return;  // no seabed at all
  const double dtheta = (hi - lo) / static_cast<double>(rays);
  const double dr = params.sample_spacing_m;
  const double window = params.pulse_window_m;
  const double kappa = 2.0 * params.absorption_db_per_m * std::log(10.0) / 10.0;
  const auto samples = static_cast<std::ptrdiff_t>(params.samples);

  for (std::size_t k = 0; k < rays; ++k) {
    const double theta = lo + (static_cast<double>(k) + 0.5) * dtheta;
    // First node whose running-minimum depression is <= theta.
    const auto it = std::lower_bound(horizon.begin(), horizon.end(), theta,
                                     [](double h, double t) { return h > t; });
    if (it == horizon.end()) continue;  // passes over the profile end
    const auto i = static_cast<std::size_t>(it - horizon.begin());
    if (i == 0) continue;  // the ray would hit the first node only at the limit
    const double ya = profile.y_m[i - 1], za = profile.z_m[i - 1];
    const double yb = profile.y_m[i], zb = profile.z_m[i];
    if (!(za == za) || !(zb == zb)) continue;  // a hole
    // Ray: (t cos theta, hs - t sin theta); facet: A + s (B - A). Solve for t, s.
    const double c = std::cos(theta), s = std::sin(theta);
    const double uy = yb - ya, uz = zb - za;
    const double den = c * uz + s * uy;  // cross(ray dir, u) with ray dir (c, -s)
    if (!(std::abs(den) > 0.0)) continue;
    const double t = (ya * uz - (za - hs) * uy) / den;  // range to the hit
    if (!(t > 0.0)) continue;
    const double len = std::hypot(uy, uz);
    // Upward unit normal of the facet (-uz, uy) / len; incidence cosine = -(ray dir . n).
    const double cos_inc = -(c * (-uz) + (-s) * uy) / len;
    if (!(cos_inc > 0.0)) continue;
    const Material& m = params.materials[profile.material[i - 1]];
    const double sigma = backscatter_sigma(params.backscatter, m, cos_inc);
    const double b2 = params.vertical_beam.two_way(theta - params.beam_axis_depression_rad);
    const double spread = params.spreading ? 1.0 / (t * t * t * t) : 1.0;
    const double atten = kappa > 0.0 ? std::exp(-kappa * t) : 1.0;
    const double power = params.calibration_k * sigma / cos_inc * b2 * params.beta_eff_rad *
                         dtheta * t * t * spread * atten;
    if (window <= 0.0) {
      const auto j = static_cast<std::ptrdiff_t>(std::floor(t / dr));
      if (j >= 0 && j < samples) out.intensity[static_cast<std::size_t>(j)] += power;
    } else {
      // Sample j holds [(j + 1) dr - w, (j + 1) dr].
      const auto j0 =
          std::max<std::ptrdiff_t>(0, static_cast<std::ptrdiff_t>(std::ceil(t / dr)) - 1);
      const auto j1 = std::min<std::ptrdiff_t>(
          samples - 1, static_cast<std::ptrdiff_t>(std::floor((t + window) / dr)) - 1);
      for (std::ptrdiff_t j = j0; j <= j1; ++j) out.intensity[static_cast<std::size_t>(j)] += power;
    }
  }
}

}  // namespace sonarsynth
