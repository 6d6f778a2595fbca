// SPDX-License-Identifier: MIT
#include "bench_render.hpp"

#include <cmath>

namespace bench {

using namespace sonarsynth;

Method default_method(int along_track_planes) {
  Method m;
  m.family = "exact";
  m.label = "default";
  const QualityConfig q;
  m.profile = q.profile;
  m.gauss_points = q.gauss_points;
  m.along_track_planes = along_track_planes;
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
  // Along-track planes exactly as Simulator.
  const AlongTrackPlanes planes =
      make_along_track_planes(sonar, m.along_track_planes, side.beta_eff_rad);
  ws.params = side;
  ws.params.truth = false;
  ws.params.gauss_points = m.gauss_points;
  const Eigen::Vector2d fwd(std::sin(pose.heading_rad), std::cos(pose.heading_rad));
  const Eigen::Vector2d stbd(fwd.y(), -fwd.x());
  for (int s = 0; s < 2; ++s) {
    const Eigen::Vector2d across = s == 1 ? stbd : Eigen::Vector2d(-stbd);
    ws.params.beam_axis_depression_rad = sonar.tilt_rad;
    for (std::size_t k = 0; k < planes.size(); ++k) {
      const double c = std::cos(planes.azimuth_rad[k]), sn = std::sin(planes.azimuth_rad[k]);
      const Eigen::Vector2d dir(c * across.x() - sn * across.y(), sn * across.x() + c * across.y());
      build_beam_profile(scene, pose.sensor_xy_m, dir, sonar.max_range_m, pose.sensor_z_m,
                         m.profile, ws.profile, ws.scratch);
      ws.params.beta_eff_rad = planes.beta_eff_rad[k];
      render_profile(ws.profile, ws.params, m, ws, ws.echo);
      for (std::size_t i = 0; i < n; ++i)
        out[static_cast<std::size_t>(s) * n + i] += ws.echo.intensity[i];
    }
  }
}

}  // namespace bench
