// SPDX-License-Identifier: MIT
// The Simulator's along-track planes: shared beam, objects between pings, the symmetric
// azimuths, the pilot poses and the automatic plane count (docs/physics.md §2.5).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "simulator_test_util.hpp"
#include "sonarsynth/along_track_planes.hpp"
#include "sonarsynth/bathy_gen.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/simulator.hpp"
#include "sonarsynth/simulator_state.hpp"

namespace sonarsynth {
namespace {

using namespace test;  // the Simulator tests' scenes, configurations and comparisons

TEST(Simulator, AlongTrackPlanesShareTheBeamAndSeeObjectsBetweenPings) {
  // On a flat seabed every plane sees the same profile and the planes share beta_eff exactly,
  // so K = 5 gives the single-plane result. A 10 cm post 0.1-0.4 m ahead of the central plane
  // at 30 m (0.2-0.8 deg, inside the 1 deg beam) is missed by the central plane alone and seen
  // by the planes at +-0.5 deg.
  Scene scene = make_scene(-60, -60, 120, 0.5, [](double, double) { return -20.0; });
  SimulationConfig cfg = plain_config();
  cfg.sonar.horizontal_beam_width_rad = rad_from_deg(1.0);
  cfg.quality.small_object_planes = false;  // the planes alone (small_object_planes_test.cpp)
  const PingPose pose = pose_at(scene, {0.0, 0.0}, 0.0, 10.0);  // heading north, stbd = +x
  auto render = [&](const Scene& s, int planes) {
    cfg.quality.along_track_planes = planes;
    Simulator sim(s, cfg, 10.0);
    auto ws = sim.make_workspace();
    RenderedPing out;
    sim.render_ping(pose, *ws, out);
    return out.starboard;
  };
  const SideOutput one_out = render(scene, 1), five_out = render(scene, 5);
  const auto& one = one_out.samples;
  const auto& five = five_out.samples;
  for (std::size_t i = 0; i < one.size(); ++i) EXPECT_NEAR(five[i], one[i], 1e-9 * one[i] + 1e-30);
  // Truth comes from the central plane, which on a flat seabed is the single plane's.
  ASSERT_EQ(five_out.truth_class.size(), one.size());
  EXPECT_TRUE(five_out.truth_class == one_out.truth_class);
  for (std::size_t i = 0; i < one.size(); ++i) {
    const double a = five_out.truth_ground_xy(i).x(), b = one_out.truth_ground_xy(i).x();
    EXPECT_TRUE(a == b || (std::isnan(a) && std::isnan(b))) << i;  // NaN: no contributor
  }
  // u = north (heading 0): 0.3 m along-track
  test::add_on_seabed(scene,
                      test::primitive(ObjectShape::kBox, 4, scene.materials.index_of("steel"),
                                      {30.0, 0.25}, {0.15, 0.05, 1.0}),
                      "post");
  const auto one_post = render(scene, 1).samples, five_post = render(scene, 5).samples;
  const std::size_t bin =
      static_cast<std::size_t>(std::sqrt(30.0 * 30.0 + 8.0 * 8.0) / cfg.sonar.sample_spacing_m());
  double d1 = 0, d5 = 0;  // extra energy near the post's top range
  for (std::size_t i = bin - 20; i < bin + 20; ++i) {
    d1 += one_post[i] - one[i];
    d5 += five_post[i] - five[i];
  }
  EXPECT_EQ(d1, 0.0);
  EXPECT_GT(d5, 0.0);
}

TEST(AlongTrackPlanes, SymmetricAzimuthsSharingBetaEffExactly) {
  SonarConfig sonar;
  sonar.horizontal_beam_width_rad = rad_from_deg(0.8);
  const double beta = sonar.beta_eff_rad();
  const AlongTrackPlanes one = make_along_track_planes(sonar, 1, beta);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one.azimuth_rad[0], 0.0);
  EXPECT_EQ(one.beta_eff_rad[0], beta);
  for (const int k : {2, 3, 9, 64}) {
    const AlongTrackPlanes p = make_along_track_planes(sonar, k, beta);
    ASSERT_EQ(p.size(), static_cast<std::size_t>(k));
    double sum = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      sum += p.beta_eff_rad[i];
      // Symmetric about the across-track direction, inside +-1.25 beam widths, weights from the
      // two-way pattern (equal for mirrored planes).
      EXPECT_NEAR(p.azimuth_rad[i], -p.azimuth_rad[p.size() - 1 - i], 1e-15);
      EXPECT_NEAR(p.beta_eff_rad[i], p.beta_eff_rad[p.size() - 1 - i], 1e-15 * beta);
      EXPECT_LT(std::abs(p.azimuth_rad[i]), 1.25 * sonar.horizontal_beam_width_rad);
    }
    EXPECT_NEAR(sum, beta, 1e-15 * k);
    // Spacing 2.5 W / K.
    EXPECT_NEAR(p.azimuth_rad[1] - p.azimuth_rad[0], 2.5 * sonar.horizontal_beam_width_rad / k,
                1e-15);
  }
  EXPECT_THROW(make_along_track_planes(sonar, 0, beta), InputError);
}

TEST(PilotPoses, SpreadOverTheGridAvoidingHolesAndOverTheSurvey) {
  Scene scene = make_scene(-50, -50, 100, 1.0, [](double, double) { return -15.0; });
  // West half is a hole: every pilot pose must stand over the east half.
  const GridGeometry& g = scene.bathymetry.geometry();
  auto& z = scene.bathymetry.mutable_heights();
  for (std::size_t r = 0; r < g.rows; ++r)
    for (std::size_t c = 0; c < g.cols / 2; ++c)
      z[r * g.cols + c] = std::numeric_limits<float>::quiet_NaN();
  const std::vector<PingPose> poses = pilot_poses(scene.bathymetry, 7.0, 10.0, 16);
  EXPECT_GE(poses.size(), 4u);  // the strata over the east half at least
  for (const PingPose& p : poses) {
    EXPECT_GE(p.sensor_xy_m.x(), g.x_of_col(static_cast<double>(g.cols / 2 - 1)));
    EXPECT_LE(p.sensor_xy_m.x(), 40.0);  // 10 m margin
    EXPECT_GE(p.sensor_xy_m.y(), -40.0);
    EXPECT_LE(p.sensor_xy_m.y(), 40.0);
    EXPECT_NEAR(p.sensor_z_m, -8.0, 1e-9);
    EXPECT_EQ(p.altitude_m, 7.0);
  }
  // Deterministic.
  const std::vector<PingPose> again = pilot_poses(scene.bathymetry, 7.0, 10.0, 16);
  ASSERT_EQ(again.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_EQ(again[i].sensor_xy_m, poses[i].sensor_xy_m);
    EXPECT_EQ(again[i].heading_rad, poses[i].heading_rad);
  }
  // A grid smaller than twice the margin: its middle.
  for (const PingPose& p : pilot_poses(scene.bathymetry, 7.0, 80.0, 4))
    EXPECT_NEAR(p.sensor_xy_m.y(), 0.0, 1e-9);
  // Over a survey: the centres of equal shares of its pings.
  VehicleConfig v;
  v.speed_m_s = 2.0;
  v.altitude_m = 8.0;
  const UtcTime t0 = std::chrono::sys_days(std::chrono::year(2026) / 5 / 4);
  const Survey survey({{"a", {{10, -40}, {10, 40}}}}, v, 0.1, t0, 1);  // 401 pings
  const std::vector<PingPose> sp = pilot_poses(survey, scene.bathymetry, 4);
  ASSERT_EQ(sp.size(), 4u);
  const std::uint64_t n = survey.total_pings();
  for (std::uint64_t k = 0; k < 4; ++k) EXPECT_EQ(sp[k].ping_index, (2 * k + 1) * n / 8);
  EXPECT_EQ(pilot_poses(survey, scene.bathymetry, 1000).size(), n);
}

TEST(Simulator, AutomaticAlongTrackPlanesOnePlaneOnAFlatSeabed) {
  const Scene scene = make_scene(-60, -60, 120, 0.5, [](double x, double y) {
    return -20.0 + 0.02 * x - 0.01 * y;  // a tilted plane: every beam plane sees the same slope
  });
  SimulationConfig cfg = plain_config();
  ASSERT_EQ(cfg.quality.along_track_planes, QualityConfig::kAutoPlanes);  // the default
  const Simulator sim(scene, cfg, 10.0);
  EXPECT_TRUE(sim.along_track().automatic);
  EXPECT_EQ(sim.along_track().planes, 1);
  EXPECT_GT(sim.along_track().pilot_pings, 0u);
  EXPECT_LT(sim.along_track().estimated_error_db, 0.01);
  // An explicit count is used as given, without a pilot.
  cfg.quality.along_track_planes = 5;
  const Simulator fixed(scene, cfg, 10.0);
  EXPECT_FALSE(fixed.along_track().automatic);
  EXPECT_EQ(fixed.along_track().planes, 5);
  EXPECT_TRUE(std::isnan(fixed.along_track().estimated_error_db));
}

TEST(Simulator, AutomaticAlongTrackPlanesMeetTheToleranceOnASeabedThatVariesAlongTrack) {
  // Sand waves with crests across the track (heading north, wavelength 1.2 m, +-0.25 m): one
  // beam plane sees a flat seabed at one height, the 1 deg beam spans several heights. The
  // choice is checked against Simulators with explicit counts: the chosen count K is within the
  // tolerance of the next count, the one before it is not.
  const Scene scene = make_scene(-60, -60, 120, 0.1, [](double, double y) {
    return -20.0 + 0.25 * std::sin(2.0 * kPi * y / 1.2);
  });
  SimulationConfig cfg = plain_config();
  cfg.sonar.horizontal_beam_width_rad = rad_from_deg(1.0);
  cfg.quality.along_track_tolerance_db = 1.0;
  const std::vector<PingPose> pilot = poses_at_y(scene, {-20.3, -7.1, 0.45, 13.0});
  const Simulator sim(scene, cfg, 10.0, pilot);
  const AlongTrackChoice& c = sim.along_track();
  ASSERT_TRUE(c.automatic);
  EXPECT_EQ(c.pilot_pings, pilot.size());
  EXPECT_GT(c.planes, 1);
  const std::vector<int> levels = {1, 3, 5, 9, 15};
  const auto at = std::find(levels.begin(), levels.end(), c.planes);
  ASSERT_NE(at, levels.end());
  auto outputs = [&](int planes) {
    SimulationConfig k = cfg;
    k.quality.along_track_planes = planes;
    return render_sides(Simulator(scene, k, 10.0), pilot);
  };
  const auto chosen = outputs(c.planes);
  if (std::next(at) != levels.end()) {
    const double d = rms_db_difference(chosen, outputs(*std::next(at)));
    EXPECT_NEAR(c.estimated_error_db, d, 0.01);
    EXPECT_LE(d, cfg.quality.along_track_tolerance_db);
  }
  const double before = rms_db_difference(outputs(*std::prev(at)), chosen);
  EXPECT_GT(before, cfg.quality.along_track_tolerance_db);
  // A looser tolerance never asks for more planes.
  cfg.quality.along_track_tolerance_db = 20.0;
  EXPECT_LE(Simulator(scene, cfg, 10.0, pilot).along_track().planes, c.planes);
}

}  // namespace
}  // namespace sonarsynth
