// SPDX-License-Identifier: MIT
#include "bench_render.hpp"

#include <cmath>

namespace bench {

using namespace sonarsynth;

Method default_method() {
  Method m;
  m.family = "exact";
  m.label = "default";
  const QualityConfig q;
  m.profile = q.profile;
  m.gauss_points = q.gauss_points;
  m.along_track_planes = q.along_track_planes;
  m.cell_m = 0.25;
  m.is_default = true;
  return m;
}

namespace {

// Keeps every n-th node of the seabed, and every node touching an object facet.
void decimate_profile(const BeamProfile& in, int n, BeamProfile& out) {
  out.clear();
  out.sensor_z_m = in.sensor_z_m;
  const std::size_t nodes = in.nodes();
  for (std::size_t i = 0; i < nodes; ++i) {
    const bool object_node = (i > 0 && in.label[i - 1] != 0) || (i + 1 < nodes && in.label[i] != 0);
    const bool keep = i == 0 || i + 1 == nodes || object_node ||
                      i % static_cast<std::size_t>(n) == 0 || !(in.z_m[i] == in.z_m[i]);
    if (!keep) continue;
    if (i == 0) {
      out.add_node(in.y_m[i], in.z_m[i]);
    } else {
      out.add_node(in.y_m[i], in.z_m[i], in.label[i - 1], in.material[i - 1]);
    }
  }
}

}  // namespace

void render_profile(const BeamProfile& profile, const SideParams& params, const Method& m,
                    PingWorkspace& ws, SideEcho& out) {
  const BeamProfile* p = &profile;
  if (m.decimate > 1) {
    decimate_profile(profile, m.decimate, ws.decimated);
    p = &ws.decimated;
  }
  if (m.rays > 0) {
    render_side_rays(*p, params, m.rays, out);
  } else {
    render_side(*p, params, out);
  }
}

void render_ping_energy(const Scene& scene, const SideParams& side, const SonarConfig& sonar,
                        const PingPose& pose, const Method& m, PingWorkspace& ws,
                        std::vector<double>& out) {
  const std::size_t n = side.samples;
  out.assign(2 * n, 0.0);
  // Along-track planes exactly as Simulator: K azimuths across +-1.25 W, weights b_h^2 sharing
  // beta_eff.
  std::vector<double> psi, beta;
  const int k_planes = m.along_track_planes;
  if (k_planes == 1) {
    psi = {0.0};
    beta = {side.beta_eff_rad};
  } else {
    const double step = 2.5 * sonar.horizontal_beam_width_rad / k_planes;
    double wsum = 0.0;
    for (int k = 0; k < k_planes; ++k) {
      psi.push_back((k - 0.5 * (k_planes - 1)) * step);
      beta.push_back(sonar.horizontal_two_way(psi.back()));
      wsum += beta.back();
    }
    for (double& b : beta) b *= side.beta_eff_rad / wsum;
  }
  ws.params = side;
  ws.params.truth = false;
  ws.params.gauss_points = m.gauss_points;
  const Eigen::Vector2d fwd(std::sin(pose.heading_rad), std::cos(pose.heading_rad));
  const Eigen::Vector2d stbd(fwd.y(), -fwd.x());
  for (int s = 0; s < 2; ++s) {
    const Eigen::Vector2d across = s == 1 ? stbd : Eigen::Vector2d(-stbd);
    ws.params.beam_axis_depression_rad = sonar.tilt_rad;
    for (std::size_t k = 0; k < psi.size(); ++k) {
      const double c = std::cos(psi[k]), sn = std::sin(psi[k]);
      const Eigen::Vector2d dir(c * across.x() - sn * across.y(), sn * across.x() + c * across.y());
      build_beam_profile(scene, pose.sensor_xy_m, dir, sonar.max_range_m, pose.sensor_z_m,
                         m.profile, ws.profile, ws.scratch);
      ws.params.beta_eff_rad = beta[k];
      render_profile(ws.profile, ws.params, m, ws, ws.echo);
      for (std::size_t i = 0; i < n; ++i)
        out[static_cast<std::size_t>(s) * n + i] += ws.echo.intensity[i];
    }
  }
}

}  // namespace bench
