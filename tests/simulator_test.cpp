// SPDX-License-Identifier: MIT
#include "sonarsynth/simulator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "simulator_test_util.hpp"
#include "sonarsynth/along_track_planes.hpp"
#include "sonarsynth/bathy_gen.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/simulator_state.hpp"

namespace sonarsynth {
namespace {

using test::add_on_seabed;
using test::make_scene;
using test::plain_config;
using test::pose_at;
using test::primitive;

struct CollectSink : PingSink {
  std::vector<RenderedPing> pings;
  std::vector<std::size_t> begun, ended;
  void begin_line(std::size_t l) override { begun.push_back(l); }
  void ping(const RenderedPing& p) override { pings.push_back(p); }
  void end_line(std::size_t l) override { ended.push_back(l); }
};

TEST(Simulator, FlatSeabedThroughTheWholePipelineMatchesTheClosedForm) {
  // docs/physics.md §3.2: E[r1, r2] = (mu beta / H^2)(F(r2) - F(r1)), F = s - s^3/3,
  // s = sqrt(1 - H^2 / r^2); the paper model uses mu = R.
  const Scene scene = make_scene(-60, -60, 120, 1.0, [](double, double) { return -30.0; });
  const SimulationConfig cfg = plain_config();
  const double H = 10.01;
  Simulator sim(scene, cfg, H);
  auto ws = sim.make_workspace();
  RenderedPing out;
  sim.render_ping(pose_at(scene, {0.3, 0.2}, 0.4, H), *ws, out);
  const double mu = scene.materials[scene.materials.index_of("sand")].paper_reflectivity;
  const double beta = cfg.sonar.beta_eff_rad();
  const double dr = cfg.sonar.sample_spacing_m();
  auto F = [&](double r) {
    if (r <= H) return 0.0;
    const double s = std::sqrt(1.0 - H * H / (r * r));
    return s - s * s * s / 3.0;
  };
  for (const SideOutput* side : {&out.port, &out.starboard}) {
    ASSERT_EQ(side->samples.size(), 800u);
    for (std::size_t i = 0; i < 800; ++i) {
      const double r1 = static_cast<double>(i) * dr, r2 = r1 + dr;
      const double expected = mu * beta / (H * H) * (F(r2) - F(r1));
      // float32 output: relative 1e-6 of the value (plus float rounding of tiny values).
      EXPECT_NEAR(side->samples[i], expected, 2e-6 * expected + 1e-30) << i;
    }
  }
}

TEST(Simulator, SameSeedSameOutputWhateverTheThreadCount) {
  const Scene scene = make_scene(-100, -100, 200, 0.5, [](double x, double y) {
    return -20.0 + 0.3 * std::sin(x / 3.0) * std::cos(y / 4.0);
  });
  SimulationConfig cfg;  // speckle, texture, TVG, quantisation: everything on
  cfg.sonar.max_range_m = 30.0;
  cfg.sonar.samples_per_channel = 512;
  SurveyLine line{"L", {{-40.0, 0.0}, {40.0, 5.0}}};
  VehicleConfig v;
  v.speed_m_s = 5.0;
  v.disturbance.roll_amplitude_rad = 0.02;
  Survey survey({line}, v, 0.05, UtcTime{}, 3);
  std::vector<std::vector<float>> first;
  for (unsigned threads : {1u, 2u, 3u}) {
    cfg.threads = threads;
    Simulator sim(scene, cfg, v.altitude_m);
    CollectSink sink;
    sim.run(survey, sink);
    ASSERT_EQ(sink.pings.size(), survey.total_pings());
    EXPECT_EQ(sink.begun, std::vector<std::size_t>{0});
    EXPECT_EQ(sink.ended, std::vector<std::size_t>{0});
    std::vector<std::vector<float>> all;
    for (const auto& p : sink.pings) {
      all.push_back(p.port.samples);
      all.push_back(p.starboard.samples);
    }
    if (first.empty()) {
      first = all;
    } else {
      EXPECT_TRUE(all == first) << threads << " threads differ";
    }
  }
  // A different seed changes the speckle.
  cfg.seed = 99;
  Simulator sim(scene, cfg, v.altitude_m);
  CollectSink sink;
  sim.run(survey, sink);
  EXPECT_NE(sink.pings[5].starboard.samples, first[11]);
}

TEST(Simulator, MirroringTheSceneSwapsPortAndStarboard) {
  // A seabed sloping across track and a box on the starboard side; mirrored about the track
  // (y -> -y, heading east), port and starboard must swap exactly.
  auto f = [](double, double y) { return -15.0 + 0.05 * y + 0.2 * std::sin(y / 2.0); };
  auto g = [&](double x, double y) { return f(x, -y); };
  Scene a = make_scene(-50, -50, 100, 0.5, f);
  Scene b = make_scene(-50, -50, 100, 0.5, g);
  for (Scene* s : {&a, &b}) {
    // Smooth steel: the built-in roughness is frozen in the local frame, not mirrored.
    Material smooth = s->materials[s->materials.index_of("steel")];
    smooth.roughness_rms_m = 0.0;
    // The box to starboard of the track (for an eastward track, -y).
    add_on_seabed(
        *s,
        primitive(ObjectShape::kBox, 5, s->materials.set(smooth), {0.0, s == &a ? -18.0 : 18.0},
                  {2.0, 1.0, 0.8}, 0.3 * (s == &a ? 1 : -1)),
        "box");
  }
  SimulationConfig cfg = plain_config();
  cfg.physics.beam_pattern = true;
  Simulator sa(a, cfg, 8.0), sb(b, cfg, 8.0);
  auto wa = sa.make_workspace(), wb = sb.make_workspace();
  RenderedPing pa, pb;
  const double east = kPi / 2;
  sa.render_ping(pose_at(a, {0.0, 0.0}, east, 8.0), *wa, pa);
  sb.render_ping(pose_at(b, {0.0, 0.0}, east, 8.0), *wb, pb);
  double energy = 0;
  for (std::size_t i = 0; i < pa.starboard.samples.size(); ++i) {
    EXPECT_NEAR(pa.starboard.samples[i], pb.port.samples[i],
                1e-9 * pa.starboard.samples[i] + 1e-30);
    EXPECT_NEAR(pa.port.samples[i], pb.starboard.samples[i], 1e-9 * pa.port.samples[i] + 1e-30);
    EXPECT_EQ(pa.starboard.truth_label[i], pb.port.truth_label[i]);
    energy += pa.starboard.samples[i];
  }
  EXPECT_GT(energy, 0.0);
  // The box is seen on starboard only, with its id.
  EXPECT_NE(std::find(pa.starboard.truth_label.begin(), pa.starboard.truth_label.end(), 5),
            pa.starboard.truth_label.end());
  EXPECT_EQ(std::find(pa.port.truth_label.begin(), pa.port.truth_label.end(), 5),
            pa.port.truth_label.end());
}

TEST(Simulator, RotationAndUtmSizedTranslationLeavePingsUnchanged) {
  // An analytic, rotation-invariant seabed (a Gaussian seamount) and a cylinder; the whole
  // scene and pose rotated by 33 deg and moved 5e5 m east, 5e6 m north (docs/physics.md §3.12).
  const double rot = rad_from_deg(33.0);
  const Eigen::Vector2d shift(5e5, 5e6);
  auto hill = [](double x, double y) {
    return -20.0 + 3.0 * std::exp(-(x * x + y * y) / (2 * 15.0 * 15.0));
  };
  auto to_rotated = [&](const Eigen::Vector2d& p) -> Eigen::Vector2d {
    return Eigen::Vector2d(std::cos(rot) * p.x() + std::sin(rot) * p.y(),
                           -std::sin(rot) * p.x() + std::cos(rot) * p.y()) +
           shift;
  };
  auto from_rotated = [&](double x, double y) -> Eigen::Vector2d {
    const Eigen::Vector2d q(x - shift.x(), y - shift.y());
    return Eigen::Vector2d(std::cos(rot) * q.x() - std::sin(rot) * q.y(),
                           std::sin(rot) * q.x() + std::cos(rot) * q.y());
  };
  Scene a = make_scene(-60, -60, 120, 0.1, hill);
  Scene b = make_scene(shift.x() - 60, shift.y() - 60, 120, 0.1, [&](double x, double y) {
    const Eigen::Vector2d p = from_rotated(x, y);
    return hill(p.x(), p.y());
  });
  // Rotating a point by +rot (clockwise in x-east/y-north) adds rot to azimuths.
  const ObjectPrimitive pipe =
      primitive(ObjectShape::kCylinder, 2, 0, {5.0, -20.0}, {15.0, 0.4, 0.4}, 0.2);
  add_on_seabed(a, pipe, "pipe");
  ObjectPrimitive pipe_b = pipe;
  pipe_b.centre_xy_m = to_rotated(pipe.centre_xy_m);
  pipe_b.heading_rad = pipe.heading_rad + rot;
  add_on_seabed(b, pipe_b, "pipe");

  SimulationConfig cfg = plain_config();
  cfg.physics.beam_pattern = true;
  cfg.physics.absorption = true;
  Simulator sa(a, cfg, 10.0), sb(b, cfg, 10.0);
  auto wa = sa.make_workspace(), wb = sb.make_workspace();
  RenderedPing pa, pb;
  const Eigen::Vector2d xy(-3.0, 4.0);
  sa.render_ping(pose_at(a, xy, 1.1, 10.0), *wa, pa);
  sb.render_ping(pose_at(b, to_rotated(xy), 1.1 + rot, 10.0), *wb, pb);
  // Bins agree within the DEM-resampling error (0.1 m grid of the same analytic surface),
  // compared as energy in 5-sample windows to stay away from single-bin edge effects.
  double total = 0, diff = 0;
  for (const auto& [sa_side, sb_side] :
       {std::pair{&pa.port, &pb.port}, std::pair{&pa.starboard, &pb.starboard}}) {
    for (std::size_t i = 0; i + 5 <= sa_side->samples.size(); i += 5) {
      double ea = 0, eb = 0;
      for (std::size_t k = i; k < i + 5; ++k) {
        ea += sa_side->samples[k];
        eb += sb_side->samples[k];
      }
      total += ea;
      diff += std::abs(ea - eb);
    }
  }
  ASSERT_GT(total, 0.0);
  EXPECT_LT(diff / total, 0.01);
}

TEST(Simulator, StableWhereMethodsFail) {
  // Holes, the grid edge, 0.5 m and 150 m altitude, a roll that points a beam above the
  // horizon, 1 and 65,535 samples: every output finite and within the output range.
  Scene scene = make_scene(-50, -50, 100, 1.0,
                           [](double x, double) { return x > 20 ? -10.0 : -10.0 + 0.05 * x; });
  auto& z = scene.bathymetry.mutable_heights();
  for (std::size_t i = 0; i < z.size(); i += 7) z[i] = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t samples : {std::size_t{1}, std::size_t{65535}, std::size_t{300}}) {
    SimulationConfig cfg;
    cfg.sonar.samples_per_channel = samples;
    cfg.sonar.max_range_m = 60.0;
    Simulator sim(scene, cfg, 10.0);
    auto ws = sim.make_workspace();
    for (double altitude : {0.5, 10.0, 150.0}) {
      for (double roll : {0.0, rad_from_deg(80.0)}) {
        for (const Eigen::Vector2d& xy : {Eigen::Vector2d(0, 0), Eigen::Vector2d(45, 45)}) {
          PingPose p = pose_at(scene, xy, 0.7, altitude);
          if (std::isnan(p.sensor_z_m)) p.sensor_z_m = -10.0 + altitude;
          p.roll_rad = roll;
          RenderedPing out;
          sim.render_ping(p, *ws, out);
          for (const SideOutput* s : {&out.port, &out.starboard}) {
            ASSERT_EQ(s->samples.size(), samples);
            for (float v : s->samples) {
              ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 32767.0f) << v;
            }
          }
          if (altitude == 150.0 && samples == 300) {
            // Nothing in range: only thermal noise (the speckle model's N), no seabed truth.
            for (auto c : out.starboard.truth_class) EXPECT_NE(c, SampleClass::seabed);
          }
        }
      }
    }
  }
}

TEST(Simulator, PaperNoiseIsAnImageDomainModelNotAmplifiedByTheTvg) {
  // Eq. (2), I' = I (1 + u) + r: E[I'] = I + sigma sqrt(pi/2), with the Rayleigh mean set
  // snr_db below the calibrated mid-range level. Averaged over many pings the far-range mean
  // must stay within that offset of the noise-free far-range mean (applied before the TVG, the
  // Rayleigh term would be amplified by 30 log R + 2 alpha R and saturate the far range).
  const Scene scene = make_scene(-100, -100, 200, 0.5, [](double, double) { return -20.0; });
  SimulationConfig cfg;
  cfg.sonar.max_range_m = 60.0;
  cfg.sonar.samples_per_channel = 600;
  cfg.output.round_to_integer = false;
  cfg.noise.snr_at_max_range_db = 20.0;
  auto far_and_mid_means = [&](NoiseConfig::Model model) {
    cfg.noise.model = model;
    Simulator sim(scene, cfg, 10.0);
    auto ws = sim.make_workspace();
    double far = 0, mid = 0;
    for (int k = 0; k < 200; ++k) {
      PingPose p = pose_at(scene, {0.0, -50.0 + 0.5 * k}, 0.0, 10.0);
      p.ping_index = static_cast<std::uint64_t>(k);
      RenderedPing out;
      sim.render_ping(p, *ws, out);
      for (std::size_t i = 540; i < 600; ++i) far += out.starboard.samples[i];
      for (std::size_t i = 270; i < 330; ++i) mid += out.starboard.samples[i];
    }
    return std::pair{far / (200 * 60), mid / (200 * 60)};
  };
  const auto [far_clean, mid_clean] = far_and_mid_means(NoiseConfig::Model::kNone);
  const auto [far_noisy, mid_noisy] = far_and_mid_means(NoiseConfig::Model::kPaper);
  const double offset = mid_clean / 100.0;  // sigma sqrt(pi/2) = mid level / 10^(20/10)
  EXPECT_NEAR(mid_noisy, mid_clean + offset, 0.03 * mid_clean);
  EXPECT_NEAR(far_noisy, far_clean + offset, 0.03 * mid_clean);
}

TEST(Simulator, RejectsInvalidConfiguration) {
  const Scene scene = make_scene(-10, -10, 20, 1.0, [](double, double) { return -5.0; });
  // Each case spoils one field of the default configuration.
  const std::vector<std::function<void(SimulationConfig&)>> spoilers = {
      [](SimulationConfig& c) { c.sonar.samples_per_channel = 0; },
      [](SimulationConfig& c) { c.quality.gauss_points = 9; },
      [](SimulationConfig& c) { c.quality.along_track_planes = 65; },
      [](SimulationConfig& c) { c.quality.along_track_tolerance_db = 0.0; },
      [](SimulationConfig& c) { c.physics.calibration_k = 0; },
      [](SimulationConfig& c) { c.sonar.sound_speed_m_s = 300; },
  };
  for (std::size_t k = 0; k < spoilers.size(); ++k) {
    SimulationConfig cfg;
    spoilers[k](cfg);
    EXPECT_THROW(Simulator(scene, cfg, 5.0), InputError) << "case " << k;
  }
}

TEST(Simulator, AGainThatRoundsTheSeabedToZeroIsRefusedBeforeRendering) {
  const Scene scene = make_scene(-60, -60, 120, 1.0, [](double, double) { return -30.0; });
  SimulationConfig cfg;
  cfg.sonar.max_range_m = 40.0;
  cfg.sonar.samples_per_channel = 400;
  cfg.quality.along_track_planes = 1;
  cfg.noise.model = NoiseConfig::Model::kNone;  // the stored seabed is then its mean
  const Simulator automatic(scene, cfg, 10.0);
  const double auto_gain_db = automatic.gain_db();
  // The automatic gain puts the mid-range seabed amplitude at max_value 10^(-12/20), i.e. its
  // power at max_value^2 10^(-12/10); 10 log10 of that over 0.25 (amplitude 0.5) lower it is at
  // half a count, where integer output rounds it to 0.
  const double floor_db =
      auto_gain_db - 10.0 * std::log10(cfg.output.max_value * cfg.output.max_value *
                                       std::pow(10.0, cfg.output.seabed_median_dbfs / 10.0) / 0.25);
  cfg.output.gain_db = floor_db + 0.1;
  EXPECT_NO_THROW(Simulator(scene, cfg, 10.0));
  cfg.output.gain_db = floor_db - 0.1;
  try {
    Simulator sim(scene, cfg, 10.0);
    ADD_FAILURE() << "gain " << cfg.output.gain_db << " dB accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("every sample would round to 0"), std::string::npos)
        << e.what();
  }
  // Float output keeps values below one count: nothing rounds away.
  cfg.output.round_to_integer = false;
  EXPECT_NO_THROW(Simulator(scene, cfg, 10.0));
}

TEST(Survey, PingTimingLaybackLeverArmAndDisturbances) {
  const Scene scene =
      make_scene(-100, -100, 200, 1.0, [](double x, double) { return -20.0 + 0.01 * x; });
  VehicleConfig v;
  v.speed_m_s = 2.0;
  v.altitude_m = 8.0;
  v.layback_m = 12.0;
  v.lever_arm_m = {0.5, 0.25, 0.1};
  v.turn_time_s = 30.0;
  v.disturbance.roll_amplitude_rad = 0.05;
  v.disturbance.heave_amplitude_m = 0.2;
  const UtcTime t0 =
      std::chrono::sys_days(std::chrono::year(2026) / 5 / 4) + std::chrono::hours(12);
  Survey s({{"a", {{-50, 0}, {50, 0}}}, {"b", {{50, 20}, {-50, 20}}}}, v, 0.1, t0, 5);
  // 100 m at 0.2 m per ping: 501 pings per line (both ends).
  EXPECT_EQ(s.pings_in_line(0), 501u);
  EXPECT_EQ(s.total_pings(), 1002u);
  const PingPose p0 = s.pose(0, scene.bathymetry);
  const PingPose p1 = s.pose(501, scene.bathymetry);
  EXPECT_EQ(p1.line, 1u);
  EXPECT_EQ(p1.time_utc - t0, std::chrono::microseconds(50'100'000 + 30'000'000));
  // The fish trails the reference by the layback, then the lever arm (heading east: forward
  // = +x, starboard = -y).
  EXPECT_NEAR(p0.heading_rad, kPi / 2, 0.06);
  EXPECT_NEAR(p0.reference_xy_m.x(), -50.0, 1e-9);
  const double h = p0.heading_rad;
  const Eigen::Vector2d fwd(std::sin(h), std::cos(h)), stbd(std::cos(h), -std::sin(h));
  const Eigen::Vector2d expected = Eigen::Vector2d(-62.0, 0.0) + 0.5 * fwd + 0.25 * stbd;
  EXPECT_NEAR((p0.sensor_xy_m - expected).norm(), 0.0, 1e-9);
  // Terrain following: altitude above the seabed under the transducers, plus heave.
  for (std::uint64_t i = 0; i < s.total_pings(); i += 37) {
    const PingPose p = s.pose(i, scene.bathymetry);
    EXPECT_NEAR(p.altitude_m, 8.0 + p.heave_m - 0.1, 1e-6);
    EXPECT_LE(std::abs(p.roll_rad), 0.05 + 1e-12);
    EXPECT_LE(std::abs(p.heave_m), 0.2 + 1e-12);
  }
  // Deterministic and smooth: the same pose twice; small change between consecutive pings.
  EXPECT_EQ(s.pose(77, scene.bathymetry).roll_rad, s.pose(77, scene.bathymetry).roll_rad);
  EXPECT_LT(std::abs(s.pose(78, scene.bathymetry).roll_rad - s.pose(77, scene.bathymetry).roll_rad),
            0.01);
  EXPECT_THROW(Survey({{"x", {{0, 0}}}}, v, 0.1, t0, 1), InputError);
  EXPECT_THROW(Survey({{"x", {{0, 0}, {1, 1}}}}, v, 0.0, t0, 1), InputError);
}

// A truth ground position is the nadir + a float ground range along the side's across-track
// direction (docs/architecture.md "Per-sample truth"). Bound: the float rounding of the range,
// |delta r| <= 2^-24 r (6 um at 100 m). Reference: the double beam-plane y of the renderer's
// central plane, with a nadir and a direction computed here from the pose (heading, pitch), over
// relief and an object.
TEST(SimulatorTruth, GroundPositionsFromFloatRangesAgreeWithTheDoublePath) {
  const Scene scene = test::with_test_box(
      make_scene(
          -150, -150, 300, 0.5,
          [](double x, double y) { return -30.0 + 0.8 * std::sin(0.21 * x) * std::cos(0.13 * y); }),
      0);
  SimulationConfig cfg = plain_config();
  cfg.sonar.max_range_m = 100.0;
  cfg.sonar.samples_per_channel = 2000;
  Simulator sim(scene, cfg, 10.0);
  auto ws = sim.make_workspace();
  const double heading = 1.45;  // starboard looks south, over the box
  PingPose pose = pose_at(scene, {12.75, 25.5}, heading, 10.0);
  pose.pitch_rad = 0.05;
  RenderedPing out;
  sim.render_ping(pose, *ws, out);

  // The starboard side is rendered last: the workspace's echo is its central plane's truth.
  const std::vector<double>& ref_y = ws->echo.truth_ground_y_m;
  const SideOutput& s = out.starboard;
  ASSERT_EQ(s.truth_ground_range_m.size(), ref_y.size());
  const Eigen::Vector2d fwd(std::sin(heading), std::cos(heading));
  const Eigen::Vector2d stbd(std::cos(heading), -std::sin(heading));
  const Eigen::Vector2d nadir = pose.sensor_xy_m + 10.0 * std::tan(0.05) * fwd;
  std::size_t placed = 0, objects = 0;
  double worst_rel = 0.0;
  for (std::size_t i = 0; i < ref_y.size(); ++i) {
    const Eigen::Vector2d got = s.truth_ground_xy(i);
    if (std::isnan(ref_y[i])) {
      EXPECT_TRUE(std::isnan(got.x()) && std::isnan(got.y())) << i;
      continue;
    }
    const Eigen::Vector2d want = nadir + ref_y[i] * stbd;
    const double bound = 0x1p-24 * std::abs(ref_y[i]) + 1e-12;
    EXPECT_NEAR(got.x(), want.x(), bound) << i;
    EXPECT_NEAR(got.y(), want.y(), bound) << i;
    worst_rel = std::max(worst_rel, (got - want).norm() / std::abs(ref_y[i]));
    ++placed;
    objects += s.truth_class[i] == SampleClass::object ? 1 : 0;
  }
  EXPECT_GT(placed, 1500u);  // relief from ~10 m to 100 m
  EXPECT_GT(objects, 10u);   // the box
  EXPECT_LT(worst_rel, 1e-7);
}

// On a flat seabed the truth position of a seabed sample lies on the side's across-track line
// through the nadir, at a ground range inside the sample's slant-range bin:
// sqrt(r1^2 - H^2) .. sqrt(r2^2 - H^2), on both sides.
TEST(SimulatorTruth, GroundPositionsOnAFlatSeabedFollowTheSlantRangeGeometry) {
  const Scene scene = make_scene(-60, -60, 120, 1.0, [](double, double) { return -30.0; });
  const SimulationConfig cfg = plain_config();
  const double H = 10.0, heading = -0.6;
  Simulator sim(scene, cfg, H);
  auto ws = sim.make_workspace();
  RenderedPing out;
  sim.render_ping(pose_at(scene, {4.25, -7.5}, heading, H), *ws, out);
  const double dr = cfg.sonar.sample_spacing_m();
  const Eigen::Vector2d stbd(std::cos(heading), -std::sin(heading));
  for (const bool starboard : {false, true}) {
    const SideOutput& s = starboard ? out.starboard : out.port;
    const Eigen::Vector2d dir = starboard ? stbd : Eigen::Vector2d(-stbd);
    std::size_t seabed = 0;
    for (std::size_t i = 0; i < s.truth_class.size(); ++i) {
      const double r1 = static_cast<double>(i) * dr, r2 = r1 + dr;
      if (s.truth_class[i] != SampleClass::seabed) {
        EXPECT_TRUE(r2 <= H + 1e-9 || !s.truth_ground_xy(i).allFinite()) << i;
        continue;
      }
      const Eigen::Vector2d d = s.truth_ground_xy(i) - Eigen::Vector2d(4.25, -7.5);
      const double along = d.dot(dir), off = d.x() * dir.y() - d.y() * dir.x();
      const double lo = r1 > H ? std::sqrt(r1 * r1 - H * H) : 0.0;
      const double hi = std::sqrt(r2 * r2 - H * H);
      const double slack = 1e-6 * hi;  // float range and the renderer's own rounding
      EXPECT_GE(along, lo - slack) << starboard << " " << i;
      EXPECT_LE(along, hi + slack) << starboard << " " << i;
      EXPECT_NEAR(off, 0.0, 1e-9) << starboard << " " << i;
      ++seabed;
    }
    EXPECT_GT(seabed, 550u) << starboard;  // 10 m .. 40 m slant range
  }
}

}  // namespace
}  // namespace sonarsynth
