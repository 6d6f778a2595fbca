// SPDX-License-Identifier: MIT
// The along-track beam planes of a run and the pilot poses of the automatic plane count.
#include "sonarsynth/along_track_planes.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "sonarsynth/error.hpp"
#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {

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
  return p;
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
