// SPDX-License-Identifier: MIT
// The benchmark scenes: (a) a flat seabed (closed form as truth), (b) a rough natural seabed,
// (c) the founding paper's pipe scene; each regenerated at any DEM cell size over a window
// around the benchmark track, and the poses of the pings rendered on it.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "sonarsynth/scene.hpp"
#include "sonarsynth/simulator.hpp"

namespace bench {

enum class SceneKind { flat, rough, paper };
const char* to_string(SceneKind k);
/// The kind to_string names; throws InputError for another name.
SceneKind parse_scene_kind(const std::string& text);

/// Sensor altitude above the flat seabed; not on a bin edge (the closed form cancels there).
inline constexpr double kFlatAltitudeM = 10.003;
inline constexpr double kFlatDepthM = 20.0;

/// The benchmark's track: pings every `spacing_m` along +x (heading east), starting at
/// `start_xy_m`, the sensor `altitude_m` above the seabed under it.
struct Track {
  Eigen::Vector2d start_xy_m = Eigen::Vector2d::Zero();
  double spacing_m = 1.0;
  int pings = 10;
  double altitude_m = 10.0;
};

/// The scene `kind` with its bathymetry generated at `cell_m` over the window that the track's
/// pings see (+-80 m across, track length + 4 m along). The paper scene keeps the objects and
/// materials of samples/paper_pipes.yaml (loaded once from `paper_yaml`).
sonarsynth::Scene make_scene(SceneKind kind, double cell_m, const Track& track,
                             const std::string& paper_yaml);
/// The track used for each scene (paper: along the southern line, the pipe 40 m to port).
Track track_for(SceneKind kind, int pings);
/// Poses of the track's pings over `scene` (heading east, level, terrain following).
std::vector<sonarsynth::PingPose> track_poses(const sonarsynth::Scene& scene, const Track& track);

/// Simulation settings of the benchmarks: the paper scene's sonar (400 kHz, 75 m, 2 x 4096
/// samples, 0.5 deg horizontal beam, paper vertical beam, tilt 20 deg), noise off, TVG none.
/// flat: beam pattern and absorption off (so the closed form applies).
sonarsynth::SimulationConfig bench_config(SceneKind kind);

}  // namespace bench
