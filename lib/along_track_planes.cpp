// SPDX-License-Identifier: MIT
// The along-track beam planes of a run and the pilot poses of the automatic plane count.
#include "sonarsynth/along_track_planes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "sonarsynth/error.hpp"
#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {

namespace {
constexpr double kInfinity = std::numeric_limits<double>::infinity();
}  // namespace

AlongTrackPlanes make_along_track_planes(const SonarConfig& sonar, int count, double beta_eff_rad) {
  if (count < 1) throw InputError("along-track planes: count < 1");
  AlongTrackPlanes p;
  if (count == 1) {
    p.azimuth_rad = {0.0};
    p.beta_eff_rad = {beta_eff_rad};
    return p;
  }
  const double step = 2.5 * sonar.horizontal_beam_width_rad / count;
  double wsum = 0.0;
  for (int k = 0; k < count; ++k) {
    const double psi = (k - 0.5 * (count - 1)) * step;
    p.azimuth_rad.push_back(psi);
    p.beta_eff_rad.push_back(sonar.horizontal_two_way(psi));
    wsum += p.beta_eff_rad.back();
  }
  for (double& b : p.beta_eff_rad) b *= beta_eff_rad / wsum;
  p.central = static_cast<std::size_t>(count / 2);
  return p;
}

double horizontal_two_way_integral(double beam_width_rad, double psi0_rad, double psi1_rad) {
  // exp(-c (psi / bw)^2) integrates to bw sqrt(pi / c) / 2 [erf(sqrt(c) psi / bw)].
  const double c = 8.0 * std::log(2.0), bw = beam_width_rad;
  const double k = std::sqrt(c) / bw;
  return 0.5 * std::sqrt(kPi / c) * bw * (std::erf(k * psi1_rad) - std::erf(k * psi0_rad));
}

ObjectPlaneRefiner::ObjectPlaneRefiner(const ObjectSet& objects, const SonarConfig& sonar,
                                       const AlongTrackPlanes& base, double beta_eff_rad)
    : base_(base),
      beam_width_rad_(sonar.horizontal_beam_width_rad),
      beta_eff_rad_(beta_eff_rad),
      half_fan_rad_(1.25 * sonar.horizontal_beam_width_rad) {
  for (const ObjectPrimitive& p : objects.primitives()) {
    const Eigen::Vector2d u = p.axis_u();
    const Eigen::Vector2d v(u.y(), -u.x());
    const Eigen::Vector2d eu = p.half_extent_m.x() * u, ev = p.half_extent_m.y() * v;
    Footprint f;
    f.centre_xy_m = p.centre_xy_m;
    f.corner_xy_m[0] = p.centre_xy_m - eu - ev;
    f.corner_xy_m[1] = p.centre_xy_m + eu - ev;
    f.corner_xy_m[2] = p.centre_xy_m + eu + ev;
    f.corner_xy_m[3] = p.centre_xy_m - eu + ev;
    f.radius_m = (eu + ev).norm();
    footprints_.push_back(f);
  }
}

bool ObjectPlaneRefiner::sees_object(const Eigen::Vector2d& nadir_xy_m,
                                     const Eigen::Vector2d& across, double max_y_m) const {
  for (const Footprint& f : footprints_) {
    if (in_fan(f, nadir_xy_m, across, max_y_m)) return true;
  }
  return false;
}

bool ObjectPlaneRefiner::in_fan(const Footprint& f, const Eigen::Vector2d& nadir_xy_m,
                                const Eigen::Vector2d& across, double max_y_m) const {
  const Eigen::Vector2d d = f.centre_xy_m - nadir_xy_m;
  const double y = d.dot(across);
  if (y + f.radius_m <= 0.0 || y - f.radius_m > max_y_m) return false;  // behind or out of range
  return std::abs(across.x() * d.y() - across.y() * d.x()) - f.radius_m <=
         std::tan(half_fan_rad_) * (y + f.radius_m);  // else outside the fan
}

bool ObjectPlaneRefiner::refine(const Eigen::Vector2d& nadir_xy_m, const Eigen::Vector2d& across,
                                double max_y_m, AlongTrackPlanes& out,
                                std::vector<double>& scratch) const {
  const double h = half_fan_rad_;
  // The base planes' largest gap (the whole fan for one plane).
  const double base_step = base_.size() > 1 ? 2.0 * h / static_cast<double>(base_.size()) : 2.0 * h;
  // Azimuth intervals [a, b] of the objects that need finer planes, and the finest step.
  scratch.clear();
  double step = base_step;
  for (const Footprint& f : footprints_) {
    if (!in_fan(f, nadir_xy_m, across, max_y_m)) continue;
    double a = kPi, b = -kPi;
    bool ahead = true;
    for (const Eigen::Vector2d& c : f.corner_xy_m) {
      const Eigen::Vector2d e = c - nadir_xy_m;
      const double ey = e.dot(across);
      // A footprint reaching under the sonar spans every azimuth: the base planes see it.
      if (!(ey > 0.0)) ahead = false;
      const double psi = std::atan2(across.x() * e.y() - across.y() * e.x(), ey);
      a = std::min(a, psi);
      b = std::max(b, psi);
    }
    if (!ahead || b <= -h || a >= h) continue;
    const double width = b - a;
    if (width >= kPlanesPerObject * base_step) continue;  // the base planes resolve it
    step = std::min(step, width / kPlanesPerObject);
    scratch.push_back(a);
    scratch.push_back(b);
  }
  if (scratch.empty()) return false;
  // At most kMaxPlanes: coarser steps (doubling) until the planes fit.
  std::size_t fine = 0;
  for (;;) {
    fine = 0;
    for (std::size_t i = 0; i < scratch.size(); i += 2) {
      fine += static_cast<std::size_t>(std::ceil(std::min(scratch[i + 1], h) / step) -
                                       std::floor(std::max(scratch[i], -h) / step)) +
              1;
    }
    if (fine + base_.size() <= kMaxPlanes) break;
    step *= 2.0;
  }
  std::vector<double>& az = out.azimuth_rad;
  az.clear();
  for (std::size_t i = 0; i < scratch.size(); i += 2) {
    const auto j0 = static_cast<long>(std::floor(std::max(scratch[i], -h) / step));
    const auto j1 = static_cast<long>(std::ceil(std::min(scratch[i + 1], h) / step));
    for (long j = j0; j <= j1; ++j) {
      const double psi = static_cast<double>(j) * step;
      if (psi >= -h && psi <= h) az.push_back(psi);
    }
  }
  std::sort(az.begin(), az.end());
  az.erase(std::unique(az.begin(), az.end()), az.end());
  // Base planes closer than step / 2 to a fine one would only make a sliver of a cell.
  const std::size_t fine_count = az.size();
  for (const double psi : base_.azimuth_rad) {
    const auto it =
        std::lower_bound(az.begin(), az.begin() + static_cast<std::ptrdiff_t>(fine_count), psi);
    const bool near =
        (it != az.begin() + static_cast<std::ptrdiff_t>(fine_count) && *it - psi < 0.5 * step) ||
        (it != az.begin() && psi - *(it - 1) < 0.5 * step);
    if (!near || psi == 0.0) az.push_back(psi);
  }
  std::sort(az.begin(), az.end());
  az.erase(std::unique(az.begin(), az.end()), az.end());
  // Shares: the pattern's integral over each plane's cell, summing to beta_eff.
  std::vector<double>& w = out.beta_eff_rad;
  w.assign(az.size(), 0.0);
  double sum = 0.0;
  for (std::size_t k = 0; k < az.size(); ++k) {
    const double lo = k == 0 ? -h : 0.5 * (az[k - 1] + az[k]);
    const double hi = k + 1 == az.size() ? h : 0.5 * (az[k] + az[k + 1]);
    w[k] = horizontal_two_way_integral(beam_width_rad_, lo, hi);
    sum += w[k];
  }
  for (double& x : w) x *= beta_eff_rad_ / sum;
  // The central plane: azimuth 0 (kept above), else the first past it.
  out.central = static_cast<std::size_t>(std::lower_bound(az.begin(), az.end(), 0.0) - az.begin());
  if (out.central == az.size()) out.central = az.size() - 1;
  return true;
}

bool object_range_window(const BeamProfile& profile, double& r_lo_m, double& r_hi_m) {
  const double hs = profile.sensor_z_m;
  // Squared slant ranges (no overflow at sonar ranges).
  double r2_lo = kInfinity, y_hi = -kInfinity, tan_min = kInfinity, r2_hi = 0.0;
  bool any = false;
  // An object's segment (y0, z0)-(y1, z1): its least distance to the sensor, its nodes' largest,
  // their ground range and tan of depression.
  const auto object_segment = [&](double y0, double z0, double y1, double z1) {
    if (!std::isfinite(z0) || !std::isfinite(z1)) return;
    any = true;
    const double dz0 = z0 - hs, uy = y1 - y0, uz = z1 - z0, uu = uy * uy + uz * uz;
    const double t = uu > 0.0 ? std::clamp(-(y0 * uy + dz0 * uz) / uu, 0.0, 1.0) : 0.0;
    const double py = y0 + t * uy, pz = dz0 + t * uz;
    r2_lo = std::min(r2_lo, py * py + pz * pz);
    for (const auto& [y, z] : {std::pair{y0, z0}, std::pair{y1, z1}}) {
      y_hi = std::max(y_hi, y);
      const double d = hs - z;
      tan_min = std::min(tan_min, y > 0.0 ? d / y : (d >= 0.0 ? kInfinity : -kInfinity));
      r2_hi = std::max(r2_hi, y * y + d * d);
    }
  };
  for (std::size_t s = 0; s < profile.sections(); ++s) {
    const std::size_t a = profile.section_start[s], b = profile.section_start[s + 1];
    for (std::size_t k = a; k < b; ++k) {
      const std::size_t k1 = k + 1 < b ? k + 1 : a;  // closed
      object_segment(profile.section_y_m[k], profile.section_z_m[k], profile.section_y_m[k1],
                     profile.section_z_m[k1]);
    }
  }
  const std::size_t n = profile.nodes();
  for (std::size_t i = 0; i + 1 < n; ++i) {
    if (profile.label[i] != 0) {
      object_segment(profile.y_m[i], profile.z_m[i], profile.y_m[i + 1], profile.z_m[i + 1]);
    }
  }
  if (!any) return false;
  bool seen = false;  // a seabed node past the objects above their horizon
  for (std::size_t i = 0; i < n && !seen; ++i) {
    const double y = profile.y_m[i], z = profile.z_m[i];
    if (!std::isfinite(z)) continue;
    r2_hi = std::max(r2_hi, y * y + (hs - z) * (hs - z));
    seen = y > y_hi && (hs - z) / y <= tan_min;
  }
  r_lo_m = std::sqrt(r2_lo);
  r_hi_m = seen ? std::sqrt(r2_hi) : kInfinity;
  return true;
}

std::vector<PingPose> pilot_poses(const Survey& survey, const HeightGrid& seabed,
                                  std::size_t count) {
  std::vector<PingPose> out;
  const std::uint64_t total = survey.total_pings();
  if (total == 0 || count == 0) return out;
  const std::uint64_t n = std::min<std::uint64_t>(count, total);
  for (std::uint64_t k = 0; k < n; ++k) {
    // Centres of n equal shares of the survey.
    out.push_back(survey.pose((2 * k + 1) * total / (2 * n), seabed));
  }
  return out;
}

std::vector<PingPose> pilot_poses(const HeightGrid& seabed, double altitude_m, double margin_m,
                                  std::size_t count) {
  std::vector<PingPose> out;
  if (seabed.empty() || count == 0) return out;
  const GridGeometry& g = seabed.geometry();
  // Column/row interval [lo, hi] kept `margin_m` from the edges where the grid is wide enough
  // (else its middle), so that the beams of the pilot pings stay on the grid.
  const auto inset = [margin_m](double cell, std::size_t nodes) {
    const double span = static_cast<double>(nodes - 1);
    const double m = std::min(margin_m / std::abs(cell), 0.5 * span);
    return std::pair{m, span - m};
  };
  const auto [c_lo, c_hi] = inset(g.dx_m, g.cols);
  const auto [r_lo, r_hi] = inset(g.dy_m, g.rows);
  const auto side = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(count))));
  constexpr std::uint64_t kPilotSeed = 0x70696c6f74ULL;  // "pilot": independent of the run's seed
  constexpr int kAttempts = 8;
  for (std::size_t k = 0; k < count; ++k) {
    const double cu = static_cast<double>(k % side), cv = static_cast<double>(k / side);
    for (int a = 0; a < kAttempts; ++a) {
      const std::uint64_t key = hash_combine(k, static_cast<std::uint64_t>(a));
      const double u =
          (cu + uniform_from_bits(keyed_hash(kPilotSeed, key, 0))) / static_cast<double>(side);
      const double v =
          (cv + uniform_from_bits(keyed_hash(kPilotSeed, key, 1))) / static_cast<double>(side);
      const double x = g.x_of_col(c_lo + u * (c_hi - c_lo));
      const double y = g.y_of_row(r_lo + v * (r_hi - r_lo));
      const double z = seabed.height_m(x, y);
      if (!std::isfinite(z)) continue;
      PingPose p;
      p.ping_index = k;
      p.sensor_xy_m = Eigen::Vector2d(x, y);
      p.reference_xy_m = p.sensor_xy_m;
      p.heading_rad = 2.0 * kPi * uniform_from_bits(keyed_hash(kPilotSeed, key, 2));
      p.altitude_m = altitude_m;
      p.sensor_z_m = z + altitude_m;
      out.push_back(p);
      break;
    }
  }
  return out;
}

}  // namespace sonarsynth
