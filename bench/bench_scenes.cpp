// SPDX-License-Identifier: MIT
#include "bench_scenes.hpp"

#include <cmath>
#include <map>
#include <memory>

#include "sonarsynth/bathy_gen.hpp"
#include "sonarsynth/enum_names.hpp"
#include "sonarsynth/formats/config/scene_file.hpp"

namespace bench {

using namespace sonarsynth;

namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr EnumName<SceneKind> kSceneKindNames[] = {
    {SceneKind::flat, "flat"}, {SceneKind::rough, "rough"}, {SceneKind::paper, "paper"}};

const Scene& paper_scene(const std::string& yaml) {
  static std::map<std::string, std::unique_ptr<Scene>> cache;
  auto& slot = cache[yaml];
  if (!slot) slot = std::make_unique<Scene>(load_scene(yaml));
  return *slot;
}
}  // namespace

const char* to_string(SceneKind k) {
  return enum_name(kSceneKindNames, k);
}

SceneKind parse_scene_kind(const std::string& text) {
  return parse_enum(kSceneKindNames, text, "--scenes");
}

Track track_for(SceneKind kind, int pings) {
  Track t;
  t.pings = pings;
  t.spacing_m = 1.0;
  t.altitude_m = kind == SceneKind::flat ? kFlatAltitudeM : 10.0;
  // Paper: along the southern line (north = -200 m), the pipe at north = -240 m is 40 m to
  // starboard when heading east.
  t.start_xy_m = kind == SceneKind::paper ? Eigen::Vector2d(-20.0, -200.0) : Eigen::Vector2d(0, 0);
  return t;
}

Scene make_scene(SceneKind kind, double cell_m, const Track& track, const std::string& paper_yaml) {
  BathyGenSpec spec;
  const double length = track.spacing_m * (track.pings - 1) + 4.0;
  const double cx = track.start_xy_m.x() + 0.5 * track.spacing_m * (track.pings - 1);
  spec.geometry = BathyGenSpec::centred_geometry(cx, track.start_xy_m.y(), length, 160.0, cell_m);
  Scene scene = kind == SceneKind::paper
                    ? Scene(paper_scene(paper_yaml).frame)
                    : Scene(GeoFrame::around(Geodetic{57.05 * kDeg, 11.20 * kDeg, 0.0}));
  switch (kind) {
    case SceneKind::flat:
      spec.depth_m = kFlatDepthM;
      break;
    case SceneKind::rough:  // samples/rough_seabed.yaml without its objects
      spec.depth_m = 18.0;
      spec.seed = 7;
      spec.components = {
          bathy::Plane::from_dip(1.0 * kDeg, 100.0 * kDeg),
          bathy::Fbm{.rms_m = 0.25, .base_wavelength_m = 30.0, .octaves = 7, .persistence = 0.55},
          bathy::Ripples{.wavelength_m = 1.6,
                         .amplitude_m = 0.04,
                         .crest_azimuth_rad = 20.0 * kDeg,
                         .asymmetry = 0.3}};
      break;
    case SceneKind::paper: {  // samples/paper_pipes.yaml
      const Scene& p = paper_scene(paper_yaml);
      spec.depth_m = 20.0;
      spec.seed = 2017;
      spec.components = {bathy::Fbm{.rms_m = 0.03, .base_wavelength_m = 8.0, .octaves = 5}};
      scene.materials = p.materials;
      scene.material_map = p.material_map;
      scene.objects = p.objects;
      scene.name = p.name;
      break;
    }
  }
  scene.bathymetry = generate_bathymetry(spec);
  return scene;
}

std::vector<PingPose> track_poses(const Scene& scene, const Track& track) {
  std::vector<PingPose> poses;
  for (int k = 0; k < track.pings; ++k) {
    PingPose p;
    p.ping_index = static_cast<std::uint64_t>(k);
    p.sensor_xy_m = track.start_xy_m + Eigen::Vector2d(k * track.spacing_m, 0.0);
    p.heading_rad = 0.5 * 3.14159265358979323846;
    const double z = scene.bathymetry.height_m(p.sensor_xy_m.x(), p.sensor_xy_m.y());
    p.altitude_m = track.altitude_m;
    p.sensor_z_m = z + track.altitude_m;
    poses.push_back(p);
  }
  return poses;
}

SimulationConfig bench_config(SceneKind kind) {
  SimulationConfig c;
  c.sonar.frequency_hz = 400e3;
  c.sonar.max_range_m = 75.0;
  c.sonar.samples_per_channel = 4096;
  c.sonar.tilt_rad = 20.0 * kDeg;
  c.sonar.horizontal_beam_width_rad = 0.5 * kDeg;
  c.sonar.vertical_beam.shape = VerticalBeamShape::paper_sine_pair;
  c.sonar.vertical_beam.upper_half_width_rad = 25.0 * kDeg;
  c.sonar.vertical_beam.lower_half_width_rad = 30.0 * kDeg;
  c.noise.model = NoiseConfig::Model::kNone;
  c.output.tvg = TvgLaw::none;
  c.output.round_to_integer = false;
  c.truth = false;
  c.threads = 1;
  if (kind == SceneKind::flat) {
    c.physics.beam_pattern = false;
    c.physics.absorption = false;
  }
  return c;
}

}  // namespace bench
