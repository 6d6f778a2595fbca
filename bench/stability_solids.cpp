// SPDX-License-Identifier: MIT
// Stability sweeps of objects as closed beam-plane sections (docs/physics.md §2.1, §3.15): a pipe
// across the beam plane over a flat seabed, built by the library (place_on_seabed,
// build_beam_profile) with 8 (fast), 16 (default), 64 and 256 segments per half circle, against
// the closed form of its circle (tests/analytic/circle_section.hpp: seabed outside the tangent
// rays' shadow plus the lit arc) per bin. Sweeps: clearance 0-5 diameters, diameter 5 cm-5 m,
// grazing angle at the pipe 0.5-45 deg.
#include "stability_solids.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "analytic/circle_section.hpp"
#include "bench_metrics.hpp"
#include "bench_render.hpp"
#include "sonarsynth/render_side.hpp"
#include "sonarsynth/scene.hpp"
#include "sonarsynth/scene_profile.hpp"

namespace bench {
namespace {

using namespace sonarsynth;

constexpr double kBeta = 0.02;
constexpr double kSeabedZ = -20.0;
constexpr double kDr = 0.02;  // slant-range bin, metres

struct PipeCase {
  double ground_m;    ///< horizontal distance of the pipe's axis from nadir
  double diameter_m;  ///< pipe diameter
  double clearance_m;
  double altitude_m;  ///< sensor height above the seabed
};

// One pipe case at every segment count: rows of the sweep `sweep` at abscissa x.
void pipe_rows(std::FILE* f, const char* sweep, double x, const PipeCase& k, bool tiny) {
  const double a = 0.5 * k.diameter_m;
  const analytic::CircleSection c{k.ground_m, k.clearance_m + a, a, k.altitude_m};
  // Past the shadow (or to 150 m when it reaches the horizon), at most 8192 bins.
  const double r_max = std::min({c.shadow_end() + 5.0, 150.0, kDr * 8192.0});
  const auto samples = static_cast<std::size_t>(std::ceil(r_max / kDr));

  Scene scene(GeoFrame(19, true, 500000.0, 5000000.0));
  const std::size_t cols = static_cast<std::size_t>(r_max) + 12;
  GridGeometry g{-5.0, 5.0, 1.0, -1.0, cols, 11};
  scene.bathymetry = HeightGrid(g, std::vector<float>(g.size(), static_cast<float>(kSeabedZ)));
  const std::uint16_t sand = scene.materials.index_of("sand");
  scene.material_map = MaterialMap(sand);
  ObjectPrimitive pipe;
  pipe.shape = ObjectShape::kCylinder;
  pipe.id = 5;
  pipe.material = sand;  // the seabed's mu: one Lambert coefficient in the closed form
  pipe.centre_xy_m = {k.ground_m, 0.0};
  pipe.half_extent_m = {3.0, a, a};  // axis north; the beam plane runs east across it
  pipe.place_on_seabed(scene.bathymetry, k.clearance_m, 0.0, "pipe");
  scene.objects.add(pipe);
  scene.objects.build_index();
  const double mu = scene.materials[sand].lambert_mu;

  std::vector<double> ref(samples);
  for (std::size_t i = 0; i < samples; ++i) {
    const double r1 = kDr * static_cast<double>(i);
    ref[i] = c.bin_energy(r1, r1 + kDr, mu, kBeta);
  }
  SideParams p;
  p.sample_spacing_m = kDr;
  p.samples = samples;
  p.beta_eff_rad = kBeta;
  p.vertical_beam.shape = VerticalBeamShape::uniform;
  p.materials = scene.materials.all();
  p.backscatter = BackscatterModel::lambert;
  const std::vector<int> counts = tiny ? std::vector<int>{16} : std::vector<int>{8, 16, 64, 256};
  for (const int n : counts) {
    Method m = default_method();
    m.family = "segments";
    m.label = "segments=" + std::to_string(n);
    m.is_default = n == ProfileOptions{}.object_segments;
    m.profile.object_segments = n;
    BeamProfile prof;
    ProfileScratch scratch;
    SideEcho e;
    const double t0 = now_s();
    build_beam_profile(scene, {0.0, 0.0}, {1.0, 0.0}, r_max + 1.0, kSeabedZ + k.altitude_m,
                       m.profile, prof, scratch);
    render_side(prof, p, e);
    const double dt = now_s() - t0;
    ErrorStats s;
    s.add(e.intensity, ref, ref.size());
    stability_row(f, sweep, x, m, s, 1e3 * dt);
  }
}

}  // namespace

void sweep_solids(const std::string& dir, bool tiny) {
  {  // A 0.5 m pipe 20 m out, 10 m below the sensor, from touching to 5 diameters up.
    std::FILE* f = open_csv(dir + "/stability_clearance.csv", kStabilityHeader);
    for (const double k : {0.0, 0.01, 0.1, 0.25, 0.5, 1.0, 2.0, 5.0}) {
      pipe_rows(f, "clearance", k, {20.0, 0.5, k * 0.5, 10.0}, tiny);
    }
    std::fclose(f);
  }
  {  // 5 cm to 5 m, half a diameter up (a 5 m pipe's top at the sensor's height).
    std::FILE* f = open_csv(dir + "/stability_pipe_size.csv", kStabilityHeader);
    for (const double d : {0.05, 0.1, 0.25, 0.5, 1.0, 2.0, 5.0}) {
      pipe_rows(f, "pipe_size", d, {20.0, d, 0.5 * d, 10.0}, tiny);
    }
    std::fclose(f);
  }
  {  // A 0.2 m pipe 40 m out resting (1 mm up), the sensor lowered to a grazing angle of 0.5 deg.
    std::FILE* f = open_csv(dir + "/stability_object_grazing.csv", kStabilityHeader);
    for (const double deg : {0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 45.0}) {
      const double h = 40.0 * std::tan(deg * 3.14159265358979323846 / 180.0);
      pipe_rows(f, "object_grazing", deg, {40.0, 0.2, 0.001, h}, tiny);
    }
    std::fclose(f);
  }
}

}  // namespace bench
