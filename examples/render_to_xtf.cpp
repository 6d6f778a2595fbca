// SPDX-License-Identifier: MIT
// Embedding sonarsynth: load a scene, render a few pings along your own trajectory and write
// them to XTF — as a robotics simulator would, one ping at a time.
//
//   render_to_xtf SCENE.yaml OUT.xtf
#include <cmath>
#include <iostream>
#include <memory>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/scene_file.hpp"
#include "sonarsynth/formats/xtf/survey_writer.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "sonarsynth/simulator.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: render_to_xtf SCENE.yaml OUT.xtf\n";
    return 2;
  }
  try {
    namespace ss = sonarsynth;
    // The Simulator shares ownership of the scene.
    const auto scene = std::make_shared<const ss::Scene>(ss::load_scene(argv[1]));

    ss::SimulationConfig config;  // defaults: 400 kHz, 75 m, 4096 samples, speckle, TVG, u16
    config.sonar.max_range_m = 40.0;
    config.sonar.samples_per_channel = 2048;
    const double altitude_m = 8.0;
    const ss::Simulator sim(scene, config, altitude_m);
    auto workspace = sim.make_workspace();  // one per thread

    // Header fields (tilt, beams, frequency, TVG flags and note) derived as `simulate` does.
    ss::xtf::WriterOptions xtf_options =
        ss::xtf_writer_options(sim, ss::xtf::SampleEncoding::kUint16, scene->name);
    xtf_options.overwrite = true;
    ss::xtf::Writer writer(argv[2], xtf_options);

    // Your vehicle's trajectory: here 50 pings heading north-east from the grid centre.
    const ss::HeightGrid& seabed = scene->bathymetry;
    const Eigen::Vector4d bounds = seabed.bounds();
    const Eigen::Vector2d centre(0.5 * (bounds[0] + bounds[2]), 0.5 * (bounds[1] + bounds[3]));
    const double heading_rad = ss::rad_from_deg(45.0);  // grid azimuth
    const Eigen::Vector2d forward(std::sin(heading_rad), std::cos(heading_rad));
    ss::RenderedPing ping;
    for (int i = 0; i < 50; ++i) {
      const Eigen::Vector2d xy = centre + 0.1 * i * forward;
      // Full pose: position (local frame, z on the bathymetry datum) and attitude (heading,
      // pitch, roll); the noise key is this ping's number (reproducible in any order).
      const Eigen::Vector3d position(xy.x(), xy.y(), seabed.height_m(xy.x(), xy.y()) + altitude_m);
      ss::PingPose pose =
          ss::sensor_pose(position, heading_rad, 0.0, ss::rad_from_deg(1.0) * std::sin(0.3 * i),
                          seabed, static_cast<std::uint64_t>(i));
      pose.ping_in_line = static_cast<std::size_t>(i);
      pose.time_utc =
          ss::UtcTime(std::chrono::seconds(1'780'000'000)) + std::chrono::milliseconds(60 * i);
      pose.speed_m_s = 1.6;
      sim.render_ping(pose, *workspace, ping);  // port/starboard samples + per-sample truth
      writer.write_ping(ss::to_xtf_ping(ping, scene->frame, config.sonar));
    }
    writer.close();
    std::cout << "wrote " << writer.pings_written() << " pings to " << writer.path().string()
              << "\n";
    return 0;
  } catch (const sonarsynth::Error& e) {
    std::cerr << "render_to_xtf: " << e.what() << "\n";
    return 1;
  }
}
