// SPDX-License-Identifier: MIT
// Scenes, configurations and poses shared by the Simulator tests.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "height_grid_test_util.hpp"
#include "object_test_util.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth::test {

// Scene on a grid of `cell` m spacing over [x0, x0 + size] x [y0, y0 + size], heights from f.
inline Scene make_scene(double x0, double y0, double size, double cell,
                        const std::function<double(double, double)>& f) {
  Scene scene(GeoFrame(31, true, 500000.0, 5000000.0));
  const auto n = static_cast<std::size_t>(std::llround(size / cell)) + 1;
  scene.bathymetry = sampled_grid({x0, y0 + size, cell, -cell, n, n}, f);
  scene.material_map = MaterialMap(scene.materials.index_of("sand"));
  return scene;
}

// Noise-free, physically plain configuration whose output is the linear intensity itself.
inline SimulationConfig plain_config() {
  SimulationConfig c;
  c.sonar.max_range_m = 40.0;
  c.sonar.samples_per_channel = 800;
  c.physics.absorption = false;
  c.physics.beam_pattern = false;
  c.noise.model = NoiseConfig::Model::kNone;
  c.output.tvg = TvgLaw::none;
  c.output.gain_db = 0.0;
  c.output.round_to_integer = false;
  c.output.max_value = 1e30;
  c.output.quantity = SampleQuantity::intensity;
  c.sensor = SensorConfig::none();
  c.threads = 1;
  return c;
}

inline PingPose pose_at(const Scene& s, Eigen::Vector2d xy, double heading, double altitude) {
  PingPose p;
  p.sensor_xy_m = xy;
  p.heading_rad = heading;
  p.sensor_z_m = s.bathymetry.height_m(xy.x(), xy.y()) + altitude;
  p.altitude_m = altitude;
  return p;
}

/// `scene` with the object tests' box: id 9, half extents 15 x 5 x 1 m, centred at x = 15 m,
/// y = 0 on the seabed, of `material` (an index into the scene's MaterialTable).
inline Scene with_test_box(Scene scene, std::uint16_t material) {
  add_on_seabed(scene, primitive(ObjectShape::kBox, 9, material, {15.0, 0.0}, {15.0, 5.0, 1.0}),
                "box");
  return scene;
}

/// Poses heading north at x = 0, 10 m above the seabed, one at each of `ys` (metres).
inline std::vector<PingPose> poses_at_y(const Scene& s, const std::vector<double>& ys) {
  std::vector<PingPose> poses;
  for (const double y : ys) poses.push_back(pose_at(s, {0.0, y}, 0.0, 10.0));
  return poses;
}

/// Port then starboard samples of each of `poses`, rendered by `sim` in one workspace.
inline std::vector<std::vector<float>> render_sides(const Simulator& sim,
                                                    const std::vector<PingPose>& poses) {
  auto ws = sim.make_workspace();
  std::vector<std::vector<float>> out;
  for (const PingPose& p : poses) {
    RenderedPing r;
    sim.render_ping(p, *ws, r);
    out.push_back(r.port.samples);
    out.push_back(r.starboard.samples);
  }
  return out;
}

/// RMS over lit bins of |10 log10(a / b)|, the difference documented for the automatic
/// along-track plane count (docs/physics.md), computed here independently of the Simulator: a
/// bin is lit if either side exceeds 1e-3 of the median positive value of b's side, and a bin
/// dark on one side only counts 40 dB.
inline double rms_db_difference(const std::vector<std::vector<float>>& a,
                                const std::vector<std::vector<float>>& b) {
  double sum = 0.0;
  std::size_t bins = 0;
  for (std::size_t s = 0; s < a.size(); ++s) {
    std::vector<double> pos;
    for (const float v : b[s])
      if (v > 0) pos.push_back(v);
    if (pos.empty()) continue;
    std::sort(pos.begin(), pos.end());
    const double lit = 1e-3 * pos[pos.size() / 2];
    for (std::size_t i = 0; i < a[s].size(); ++i) {
      const double x = a[s][i], y = b[s][i];
      if (!(x > lit || y > lit)) continue;
      const double d = (x <= 1e-4 * y || y <= 1e-4 * x) ? 40.0 : std::abs(10 * std::log10(x / y));
      sum += d * d;
      ++bins;
    }
  }
  return bins ? std::sqrt(sum / static_cast<double>(bins)) : 0.0;
}

/// Speckle and texture, single look, no thermal or receiver noise: the output is the clean
/// intensity times the texture T times the speckle S.
inline SimulationConfig speckle_config(bool texture) {
  SimulationConfig c = plain_config();
  c.noise.model = NoiseConfig::Model::kSpeckle;
  c.noise.snr_at_max_range_db = 250.0;
  c.noise.texture = texture;
  c.output.detector_sub_samples = 1;
  return c;
}

}  // namespace sonarsynth::test
