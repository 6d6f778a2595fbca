// SPDX-License-Identifier: MIT
// Scenes, configurations and poses shared by the Simulator tests.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "object_test_util.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth::test {

// Scene on a grid of `cell` m spacing over [x0, x0 + size] x [y0, y0 + size], heights from f.
inline Scene make_scene(double x0, double y0, double size, double cell,
                        const std::function<double(double, double)>& f) {
  Scene scene(GeoFrame(31, true, 500000.0, 5000000.0));
  const auto n = static_cast<std::size_t>(std::llround(size / cell)) + 1;
  GridGeometry g{x0, y0 + size, cell, -cell, n, n};
  std::vector<float> z(g.size());
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t c = 0; c < n; ++c) {
      z[r * n + c] = static_cast<float>(
          f(g.x_of_col(static_cast<double>(c)), g.y_of_row(static_cast<double>(r))));
    }
  }
  scene.bathymetry = HeightGrid(g, std::move(z));
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
