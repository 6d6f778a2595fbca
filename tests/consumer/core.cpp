// SPDX-License-Identifier: MIT
// Component core: generates a seabed and renders one ping, no file I/O.
#include <iostream>

#include "sonarsynth/bathy_gen.hpp"
#include "sonarsynth/simulator.hpp"

int main() {
  sonarsynth::BathyGenSpec spec;
  spec.depth_m = 20.0;
  spec.geometry = sonarsynth::BathyGenSpec::centred_geometry(0.0, 0.0, 100.0, 100.0, 1.0);
  sonarsynth::Scene scene(sonarsynth::GeoFrame(19, true, 500000.0, 5000000.0));
  scene.bathymetry = sonarsynth::generate_bathymetry(spec);
  sonarsynth::SimulationConfig config;
  config.sonar.max_range_m = 30.0;
  config.sonar.samples_per_channel = 256;
  config.threads = 1;
  const sonarsynth::Simulator sim(scene, config, 10.0);
  auto ws = sim.make_workspace();
  sonarsynth::PingPose pose;
  pose.sensor_z_m = -10.0;
  pose.altitude_m = 10.0;
  sonarsynth::RenderedPing ping;
  sim.render_ping(pose, *ws, ping);
  std::cout << "core: " << ping.port.samples.size() << " samples per side\n";
  return ping.port.samples.size() == 256 ? 0 : 1;
}
