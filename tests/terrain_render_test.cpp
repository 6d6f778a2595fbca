// SPDX-License-Identifier: MIT
// Rendering coarse DEMs (docs/physics.md, "Seabed interpolation"): a bicubic 8 m DEM of a smooth
// surface renders closer to the same surface sampled at 0.25 m than the bilinear 8 m DEM does,
// and the automatic along-track plane count sees roughness added on top of a file DEM.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "simulator_test_util.hpp"
#include "sonarsynth/bathy_gen.hpp"

namespace sonarsynth {
namespace {

using namespace test;  // the Simulator tests' scenes, configurations and comparisons

// Both sides of pings at `xy` (heading north, 10 m above the surface `f`).
std::vector<std::vector<float>> render(const Scene& scene, const std::vector<Eigen::Vector2d>& xy,
                                       const std::function<double(double, double)>& f) {
  SimulationConfig cfg = plain_config();
  cfg.quality.along_track_planes = 1;
  std::vector<PingPose> poses;
  for (const Eigen::Vector2d& p : xy) {
    poses.push_back(pose_at(scene, p, 0.0, 10.0));
    poses.back().sensor_z_m = f(p.x(), p.y()) + 10.0;  // the same sensor height in every scene
  }
  return render_sides(Simulator(scene, cfg, 10.0), poses);
}

TEST(TerrainRender, BicubicCoarseDemIsCloserToTheFineSurfaceThanBilinear) {
  // Smooth relief: +-2.5 m over wavelengths of 50 and 60 m, on a gentle slope.
  const auto f = [](double x, double y) {
    return -20.0 + 0.03 * x + 2.5 * std::sin(2.0 * kPi * x / 50.0) * std::cos(2.0 * kPi * y / 60.0);
  };
  const Scene fine = make_scene(-64, -64, 128, 0.25, f);
  const Scene bilinear = make_scene(-64, -64, 128, 8.0, f);
  Scene bicubic = make_scene(-64, -64, 128, 8.0, f);
  bicubic.bathymetry.set_interpolation(Interpolation::kBicubic);
  const std::vector<Eigen::Vector2d> xy = {{0, -20}, {3, -7.5}, {-2, 5}, {1, 17}, {-4, 31}};
  const auto ref = render(fine, xy, f);
  const double e_lin = rms_db_difference(render(bilinear, xy, f), ref);
  const double e_cub = rms_db_difference(render(bicubic, xy, f), ref);
  std::cout << "8 m DEM vs 0.25 m DEM, dB RMS per bin: bilinear " << e_lin << ", bicubic " << e_cub
            << "\n";
  RecordProperty("bilinear_db_rms", std::to_string(e_lin));
  RecordProperty("bicubic_db_rms", std::to_string(e_cub));
  EXPECT_LT(e_cub, 0.75 * e_lin);
}

// Stair steps: 10 log10 of the samples over a window of ground range, and how much of the
// brightness change between neighbouring bins comes in steps: the largest |change| over the
// mean |change|. A bilinear DEM is planar between the nodes along a grid axis, so its slope (and
// the backscatter) jumps at every cell edge, every ~10 bins here: most of the change comes in
// those jumps. A C1 surface changes the slope continuously.
double step_ratio(const std::vector<float>& side, std::size_t from, std::size_t to) {
  double max_d = 0.0, sum_d = 0.0;
  for (std::size_t i = from; i + 1 < to; ++i) {
    const double d = std::abs(10.0 * std::log10(double(side[i + 1]) / double(side[i])));
    max_d = std::max(max_d, d);
    sum_d += d;
  }
  return max_d / (sum_d / static_cast<double>(to - from - 1));
}

TEST(TerrainRender, BicubicRemovesTheStairStepsOfACloseRangeDem) {
  // A 0.5 m DEM (as samples/real_ledges.yaml's BAG) of smooth undulations 4.5 m long, 0.08 m
  // high, seen from 10 m at 5 cm bins: ground ranges 11-19 m (grazing 28-42 deg, no shadows).
  const auto f = [](double x, double y) {
    return -20.0 + 0.08 * std::sin(2.0 * kPi * x / 4.5) + 0.05 * std::cos(2.0 * kPi * y / 7.0);
  };
  const Scene bilinear = make_scene(-32, -32, 64, 0.5, f);
  Scene bicubic = bilinear;
  bicubic.bathymetry.set_interpolation(Interpolation::kBicubic);
  const std::vector<Eigen::Vector2d> xy = {{0.1, -3.3}, {0.3, 1.2}, {-0.2, 6.4}};
  const auto lin = render(bilinear, xy, f);
  const auto cub = render(bicubic, xy, f);
  // Bins of slant ranges 14.9-21.5 m (5 cm bins, altitude 10 m).
  const std::size_t from = 298, to = 430;
  double worst_cub = 0.0, best_lin = 1e9;
  for (std::size_t s = 0; s < lin.size(); ++s) {
    for (std::size_t i = from; i < to; ++i) {
      ASSERT_GT(lin[s][i], 0.0f) << s << " " << i;
      ASSERT_GT(cub[s][i], 0.0f) << s << " " << i;
    }
    best_lin = std::min(best_lin, step_ratio(lin[s], from, to));
    worst_cub = std::max(worst_cub, step_ratio(cub[s], from, to));
  }
  std::cout << "largest / mean bin-to-bin brightness change: bilinear >= " << best_lin
            << ", bicubic <= " << worst_cub << "\n";
  // Measured: bilinear 7.1, bicubic 2.7.
  EXPECT_GT(best_lin, 5.0);
  EXPECT_LT(worst_cub, 3.5);
  EXPECT_GT(best_lin, 2.0 * worst_cub);
}

TEST(TerrainRender, AutomaticPlaneCountSeesComponentsAddedToAFileDem) {
  // A coarse flat "file" DEM: one beam plane suffices. Ripples added at 0.1 m with crests
  // across the track (running east, heading north) vary along track within the beam: the pilot
  // pings render the refined grid and ask for more planes. Each beam plane sees a flat seabed at
  // its own height, so the planes differ most near the first return.
  const auto plane = [](double, double) { return -20.0; };
  Scene coarse = make_scene(-60, -60, 120, 8.0, plane);
  coarse.bathymetry.set_interpolation(Interpolation::kBicubic);
  SimulationConfig cfg = plain_config();
  cfg.sonar.horizontal_beam_width_rad = rad_from_deg(1.0);
  cfg.quality.along_track_tolerance_db = 1.0;
  std::vector<PingPose> pilot = poses_at_y(coarse, {-20.3, -7.1, 0.45, 13.0});
  const Simulator plain(coarse, cfg, 10.0, pilot);
  ASSERT_TRUE(plain.along_track().automatic);
  EXPECT_EQ(plain.along_track().planes, 1);

  Scene rough = coarse;
  rough.bathymetry =
      resample(coarse.bathymetry, refined_geometry(coarse.bathymetry.geometry(), 0.1));
  BathyGenSpec spec;
  spec.geometry = rough.bathymetry.geometry();
  bathy::Ripples r;
  r.wavelength_m = 1.2;
  r.amplitude_m = 0.25;
  r.crest_azimuth_rad = 0.5 * kPi;
  r.ref_y_m = 0.3;  // a crest at y = 0.3: z = 0.25 cos(2 pi (y - 0.3) / 1.2)
  r.bandwidth = 0.0;
  spec.components = {r};
  add_bathymetry_components(spec, rough.bathymetry);
  // The pilot as pilot_poses() places it: the sensor 10 m above the (refined) seabed.
  for (PingPose& p : pilot) p = pose_at(rough, p.sensor_xy_m, 0, 10);
  const Simulator sim(rough, cfg, 10.0, pilot);
  ASSERT_TRUE(sim.along_track().automatic);
  std::cout << "automatic planes: file DEM " << plain.along_track().planes << " ("
            << plain.along_track().estimates_db.front() << " dB 1 vs 3 planes), with ripples "
            << sim.along_track().planes << " (" << sim.along_track().estimates_db.front()
            << " dB)\n";
  EXPECT_LT(plain.along_track().estimates_db.front(), 1e-9);
  EXPECT_GT(sim.along_track().planes, 1);
  EXPECT_GT(sim.along_track().estimates_db.front(), cfg.quality.along_track_tolerance_db);
}

}  // namespace
}  // namespace sonarsynth
