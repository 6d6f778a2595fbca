// SPDX-License-Identifier: MIT
// The sensor stage (docs/physics.md §1.10): amplitude output, the detector, the automatic gain's
// target, the receiver noise floor, volume reverberation, shadow fill, the first bottom return
// and the ring-down, each against a closed form or an independent computation.
#include "sonarsynth/sensor_effects.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "simulator_test_util.hpp"
#include "sonarsynth/simd.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {
namespace {

constexpr double kSeabedZ = -30.0;
constexpr double kAltitude = 10.0;

// A flat sand seabed; with `wall`, a 6 m high ridge 8-10 m east of x = 0 (north-south).
std::shared_ptr<const Scene> scene_with(bool wall) {
  return std::make_shared<const Scene>(
      test::make_scene(-60, -60, 120, 0.5, [wall](double x, double) {
        return wall && x >= 8.0 && x <= 10.0 ? kSeabedZ + 6.0 : kSeabedZ;
      }));
}

SimulationConfig base_config() {
  SimulationConfig c;
  c.sonar.max_range_m = 30.0;
  c.sonar.samples_per_channel = 600;
  c.quality.along_track_planes = 1;
  c.noise.texture = false;
  c.noise.snr_at_max_range_db = 300.0;  // thermal noise out of the way
  c.sensor = SensorConfig::none();
  c.threads = 1;
  return c;
}

// base_config without speckle: the output is the intensity itself, not rounded.
SimulationConfig intensity_config() {
  SimulationConfig c = base_config();
  c.noise.model = NoiseConfig::Model::kNone;
  c.output.quantity = SampleQuantity::intensity;
  c.output.round_to_integer = false;
  return c;
}

PingPose pose_at(const Scene& s, double y, std::uint64_t key) {
  return sensor_pose(Eigen::Vector3d(0.0, y, kSeabedZ + kAltitude), 0.0, 0.0, 0.0, s.bathymetry,
                     key);
}

RenderedPing render(const Simulator& sim, const PingPose& pose) {
  auto ws = sim.make_workspace();
  RenderedPing out;
  sim.render_ping(pose, *ws, out);
  return out;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

TEST(SensorEffects, AmplitudeIsTheSquareRootOfTheIntensity) {
  const auto scene = scene_with(false);
  SimulationConfig c = base_config();
  c.noise.model = NoiseConfig::Model::kNone;
  c.output.gain_db = 50.0;
  c.output.round_to_integer = false;
  c.output.max_value = 3.0e38;
  c.output.quantity = SampleQuantity::intensity;
  const RenderedPing intensity = render(Simulator(scene, c, kAltitude), pose_at(*scene, 0, 1));
  c.output.quantity = SampleQuantity::amplitude;
  const RenderedPing amplitude = render(Simulator(scene, c, kAltitude), pose_at(*scene, 0, 1));
  std::size_t lit = 0;
  for (std::size_t i = 0; i < 600; ++i) {
    const double a = amplitude.starboard.samples[i], p = intensity.starboard.samples[i];
    EXPECT_NEAR(a * a, p, 1e-6 * p) << i;
    lit += p > 0.0;
  }
  EXPECT_GT(lit, 300u);
}

// Ratio of stored to noise-free samples over the seabed of `pings` pings: the detector's output
// for a unit-mean seabed, whose median has a closed form.
std::vector<double> unit_mean_looks(const SimulationConfig& c, int pings) {
  const auto scene = scene_with(false);
  const Simulator sim(scene, c, kAltitude);
  std::vector<double> ratio2;
  for (int k = 0; k < pings; ++k) {
    const RenderedPing p =
        render(sim, pose_at(*scene, -20.0 + 0.8 * k, static_cast<std::uint64_t>(k)));
    for (const SideOutput* s : {&p.port, &p.starboard}) {
      for (std::size_t i = 300; i < 580; ++i) {  // 15-29 m slant range: lit seabed
        const double a = s->samples[i], m = s->clean_samples[i];
        ratio2.push_back((a * a) / (m * m));
      }
    }
  }
  return ratio2;
}

TEST(SensorEffects, DetectorMediansMatchTheirClosedForms) {
  SimulationConfig c = base_config();
  c.clean_samples = true;
  c.output.round_to_integer = false;  // no rounding of the ratio
  // Single look: |z|^2 ~ Exp(1), median ln 2.
  c.output.detector_sub_samples = 1;
  EXPECT_NEAR(median(unit_mean_looks(c, 40)), std::log(2.0), 0.04);
  // Peak of N looks: P(max <= x) = (1 - e^-x)^N = 1/2 at x = -ln(1 - 2^(-1/N)).
  for (int n : {3, 5}) {
    c.output.detector_sub_samples = n;
    const double expected = -std::log(1.0 - std::pow(2.0, -1.0 / n));
    EXPECT_NEAR(median(unit_mean_looks(c, 40)), expected, 0.04 * expected) << n;
  }
}

TEST(SensorEffects, AutomaticGainPutsTheSeabedMedianAtTheTarget) {
  const auto scene = scene_with(false);
  for (double target_dbfs : {-12.0, -20.0}) {
    SimulationConfig c = base_config();
    c.output.seabed_median_dbfs = target_dbfs;
    c.output.tvg = TvgLaw::spherical;
    const Simulator sim(scene, c, kAltitude);
    std::vector<double> mid;
    for (int k = 0; k < 60; ++k) {
      const RenderedPing p =
          render(sim, pose_at(*scene, -25.0 + 0.8 * k, static_cast<std::uint64_t>(k)));
      for (const SideOutput* s : {&p.port, &p.starboard}) {
        for (std::size_t i = 270; i < 330; ++i) mid.push_back(s->samples[i]);  // 13.5-16.5 m
      }
    }
    const double level_db = 20.0 * std::log10(median(mid) / c.output.max_value);
    EXPECT_NEAR(level_db, target_dbfs, 0.5);
  }
}

// Mean stored power of the water column (slant range < altitude - 2 samples) over `pings` pings.
double water_column_power(const SimulationConfig& c, int pings, bool* any_zero = nullptr) {
  const auto scene = scene_with(false);
  const Simulator sim(scene, c, kAltitude);
  double sum = 0.0;
  std::size_t count = 0;
  const auto n = static_cast<std::size_t>(kAltitude / c.sonar.sample_spacing_m()) - 2;
  for (int k = 0; k < pings; ++k) {
    const RenderedPing p = render(sim, pose_at(*scene, 0.0, static_cast<std::uint64_t>(k)));
    for (const SideOutput* s : {&p.port, &p.starboard}) {
      for (std::size_t i = 0; i < n; ++i) {
        sum += double{s->samples[i]} * s->samples[i];
        if (any_zero != nullptr && s->samples[i] == 0.0f) *any_zero = true;
      }
      count += n;
    }
  }
  return sum / static_cast<double>(count);
}

TEST(SensorEffects, ReceiverNoiseFloorHasItsRmsLevelAndNoZeros) {
  SimulationConfig c = base_config();
  c.output.round_to_integer = false;
  c.sensor.noise_floor_dbfs = -40.0;
  const double floor_power = std::pow(c.output.max_value * 0.01, 2.0);
  c.output.detector_sub_samples = 1;
  EXPECT_NEAR(water_column_power(c, 40), floor_power, 0.03 * floor_power);
  // The peak of three exponential looks has mean 1 + 1/2 + 1/3.
  c.output.detector_sub_samples = 3;
  c.output.round_to_integer = true;
  bool zero = false;
  const double expected = floor_power * (1.0 + 0.5 + 1.0 / 3.0);
  EXPECT_NEAR(water_column_power(c, 40, &zero), expected, 0.03 * expected);
  EXPECT_FALSE(zero);
}

TEST(SensorEffects, VolumeReverberationAndShadowFillHaveTheirLevels) {
  const auto scene = scene_with(true);
  SimulationConfig c = intensity_config();
  c.sensor.volume_reverberation_db = -40.0;
  c.sensor.shadow_fill_db = -24.0;
  c.output.tvg_spreading_db_per_decade = 30.0;  // the compensating TVG (20: the TVG law test)
  const Simulator sim(scene, c, kAltitude);
  const RenderedPing p = render(sim, pose_at(*scene, 0.0, 1));
  // Without noise and speckle, the automatic gain puts the mid-range seabed mean (the levels'
  // reference) at max_value 10^(seabed_median_dbfs/10), so volume reverberation at the reference
  // altitude is that times 10^(-40/10), growing in proportion to the range, and shadow fill adds a
  // constant 10^(-24/10) of it.
  const double ref = c.output.max_value * std::pow(10.0, c.output.seabed_median_dbfs / 10.0);
  const double dr = c.sonar.sample_spacing_m();
  std::size_t water = 0, shadow = 0;
  for (std::size_t i = 0; i < 600; ++i) {
    const double r = (static_cast<double>(i) + 0.5) * dr;
    const double volume = ref * 1e-4 * r / kAltitude;
    const SampleClass cls = p.starboard.truth_class[i];
    if (cls == SampleClass::water_column && r < kAltitude - dr) {
      EXPECT_NEAR(p.starboard.samples[i], volume, 1e-5 * volume) << i;
      ++water;
    } else if (cls == SampleClass::shadow) {
      const double fill = ref * std::pow(10.0, -2.4);
      EXPECT_NEAR(p.starboard.samples[i], fill + volume, 1e-5 * (fill + volume)) << i;
      ++shadow;
    }
  }
  EXPECT_GT(water, 150u);  // the ridge top is nearer than the seabed below
  EXPECT_GT(shadow, 50u);
}

TEST(SensorEffects, FirstBottomReturnMatchesAnIndependentQuadratureAndStartsAtTheAltitude) {
  const auto scene = scene_with(false);
  SimulationConfig c = intensity_config();
  c.output.tvg = TvgLaw::none;
  c.output.gain_db = 0.0;
  c.output.max_value = 3.0e38;
  const RenderedPing off = render(Simulator(scene, c, kAltitude), pose_at(*scene, 0.0, 1));
  c.sensor.first_return_reflection_db = -10.0;
  c.sensor.first_return_rms_slope = 0.15;
  c.sensor.side_lobe_db = -18.0;
  const Simulator sim(scene, c, kAltitude);
  const RenderedPing on = render(sim, pose_at(*scene, 0.0, 1));
  // Independent: 20000-point midpoint rule in across-track distance y over each bin, the same
  // integrand K beta rho / (8 s^2 cos^4) e^(-tan^2 / 2 s^2) max(b^2, side lobe^2) r^-3 e^-kappa r.
  const double dr = c.sonar.sample_spacing_m(), h = kAltitude, s2 = 0.15 * 0.15;
  const double kappa = 2.0 * sim.absorption_db_per_m() * std::log(10.0) / 10.0;
  const double coef = c.physics.calibration_k * c.sonar.beta_eff_rad() * 0.1 / (8.0 * s2);
  const VerticalBeamPattern& beam = c.sonar.vertical_beam;
  const auto first = static_cast<std::size_t>(h / dr);
  for (std::size_t i = 0; i < 600; ++i) {
    const double diff = double{on.starboard.samples[i]} - off.starboard.samples[i];
    const double r0 = static_cast<double>(i) * dr, r1 = r0 + dr;
    double expected = 0.0;
    if (r1 > h) {
      const double y0 = r0 > h ? std::sqrt(r0 * r0 - h * h) : 0.0;
      const double y1 = std::sqrt(r1 * r1 - h * h);
      const int m = 20000;
      for (int k = 0; k < m; ++k) {
        const double y = y0 + (k + 0.5) * (y1 - y0) / m;
        const double r = std::hypot(y, h), cos_t = h / r, tan_t = y / h;
        const double b2 =
            std::max(beam.two_way(std::atan2(h, y) - c.sonar.tilt_rad), std::pow(10.0, -3.6));
        expected += std::exp(-tan_t * tan_t / (2.0 * s2)) / std::pow(cos_t, 4) * b2 / (r * r * r) *
                    std::exp(-kappa * r) * (y1 - y0) / m;
      }
      expected *= coef;
    }
    if (i < first) {
      EXPECT_EQ(diff, 0.0) << i;  // nothing before 2H/c
    } else {
      EXPECT_NEAR(diff, expected, 1e-4 * expected + 1e-6 * off.starboard.samples[i]) << i;
    }
  }
  // The near-normal return dominates the first bin (the diffuse seabed there is seen through the
  // lower edge of the main lobe).
  EXPECT_GT(double{on.starboard.samples[first]}, 5.0 * off.starboard.samples[first]);
}

TEST(SensorEffects, TermsKeptBetweenPingsEqualThoseOfAFreshWorkspace) {
  // A workspace keeps the first return of the last altitude and the patch textures' rows between
  // pings: pings rendered in one workspace, in an order that revisits altitudes and along-track
  // patches and jumps back, must equal each ping rendered alone in a fresh workspace, bit for bit.
  const auto scene = scene_with(true);
  SimulationConfig c = intensity_config();
  c.sensor.volume_reverberation_db = -20.0;
  c.sensor.shadow_fill_db = -15.0;
  c.sensor.first_return_reflection_db = -10.0;
  c.sensor.volume_texture_shape = 0.5;
  c.sensor.shadow_fill_texture_shape = 0.3;
  c.sensor.volume_patch_along_track_m = 0.3;
  c.sensor.volume_patch_range_m = 0.1;
  const Simulator sim(scene, c, kAltitude);
  const double altitudes[] = {10.0, 10.0, 10.0, 9.5, 9.5, 10.0, 11.0, 10.0, 10.0, 9.5};
  const double along[] = {0.0, 0.1, 0.2, 0.3, 0.45, 0.1, 5.0, 0.05, 0.55, 0.6};
  auto kept = sim.make_workspace();
  std::size_t compared = 0;
  for (std::size_t k = 0; k < std::size(along); ++k) {
    PingPose pose = sensor_pose(Eigen::Vector3d(0.0, along[k], kSeabedZ + altitudes[k]), 0.0, 0.0,
                                0.0, scene->bathymetry, k + 1);
    pose.along_track_m = along[k];
    RenderedPing a;
    sim.render_ping(pose, *kept, a);
    const RenderedPing b = render(sim, pose);
    for (const auto& [x, y] :
         {std::pair{&a.port, &b.port}, std::pair{&a.starboard, &b.starboard}}) {
      ASSERT_EQ(x->samples.size(), y->samples.size());
      for (std::size_t i = 0; i < x->samples.size(); ++i) {
        ASSERT_EQ(x->samples[i], y->samples[i]) << "ping " << k << " sample " << i;
        compared += x->samples[i] > 0.0f;
      }
    }
  }
  EXPECT_GT(compared, 10000u);
}

TEST(SensorEffects, SpeckleCorrelatesAlongTrackAsTheFootprintsOverlap) {
  // Pings 0.25 m apart along a straight track; the footprint L = r beta_eff (docs/physics.md
  // §1.6) grows with range from 0.6 to 1.5 times the spacing. The Gaussian beam gives
  // exp(-1.571 (d / L)^2): within 0.1 of 1 - (d / L)^2 up to d = 0.9 L, below 0.2 from d = L on.
  // Intensity, one look, no thermal noise: the ratio of noisy to noise-free samples is the speckle
  // field itself.
  const auto scene = scene_with(false);
  SimulationConfig c = base_config();
  c.output.quantity = SampleQuantity::intensity;
  c.output.detector_sub_samples = 1;
  c.output.round_to_integer = false;
  c.clean_samples = true;
  c.noise.aperture_translation = false;  // the far-field footprint alone
  const Simulator sim(scene, c, kAltitude);
  const double spacing = 0.25, dr = c.sonar.sample_spacing_m();
  // The speckle field of `pings` pings along the track: noisy over noise-free samples.
  std::vector<std::vector<double>> field;
  auto sample_field = [&](const Simulator& s, int pings) {
    field.clear();
    for (int k = 0; k < pings; ++k) {
      PingPose pose = pose_at(*scene, -30.0 + spacing * k, static_cast<std::uint64_t>(k));
      pose.along_track_m = spacing * k;
      const RenderedPing p = render(s, pose);
      std::vector<double> f(600);
      for (std::size_t i = 0; i < 600; ++i) {
        f[i] = p.starboard.clean_samples[i] > 0.0f
                   ? double{p.starboard.samples[i]} / p.starboard.clean_samples[i]
                   : 0.0;
      }
      field.push_back(f);
    }
  };
  sample_field(sim, 240);
  // Pearson correlation of consecutive pings over samples [i0, i1).
  auto lag1 = [&](std::size_t i0, std::size_t i1) {
    double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0, n = 0;
    for (std::size_t k = 0; k + 1 < field.size(); ++k) {
      for (std::size_t i = i0; i < i1; ++i) {
        const double x = field[k][i], y = field[k + 1][i];
        sx += x, sy += y, sxx += x * x, syy += y * y, sxy += x * y, n += 1;
      }
    }
    const double cov = sxy / n - sx / n * sy / n;
    return cov / std::sqrt((sxx / n - sx * sx / n / n) * (syy / n - sy * sy / n / n));
  };
  std::size_t above = 0, below = 0;
  for (std::size_t i0 = 240; i0 + 20 <= 580; i0 += 20) {  // 12-29 m, past the first return
    const double r = (static_cast<double>(i0) + 10.0) * dr;
    const double ratio = spacing / (r * c.sonar.beta_eff_rad());
    const double measured = lag1(i0, i0 + 20);
    if (ratio > 1.05) {
      EXPECT_LE(measured, 0.2) << "r = " << r << " spacing / footprint = " << ratio;
      ++above;
    } else if (ratio <= 0.9) {
      EXPECT_NEAR(measured, 1.0 - ratio * ratio, 0.1) << "r = " << r << " ratio " << ratio;
      ++below;
    }
  }
  EXPECT_GE(above, 2u);
  EXPECT_GE(below, 5u);
  // The legacy per-seabed-cell speckle: cells of one range resolution (5 cm) are 5 times finer
  // than the spacing, so consecutive pings are independent at every range.
  c.noise.along_track_correlation = false;
  const Simulator legacy(scene, c, kAltitude);
  sample_field(legacy, 120);
  EXPECT_LT(std::abs(lag1(400, 580)), 0.1);
}

TEST(SensorEffects, RingDownSaturatesTheFirstSamples) {
  const auto scene = scene_with(false);
  SimulationConfig c = base_config();
  c.sensor.ring_down_m = 0.2;  // dr = 0.05: samples 0-3 (centres 0.025 .. 0.175 m)
  const RenderedPing p = render(Simulator(scene, c, kAltitude), pose_at(*scene, 0.0, 1));
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(p.port.samples[i], 32767.0f) << i;
  EXPECT_LT(p.port.samples[4], 32767.0f);
  EXPECT_EQ(p.port.saturated, 0u);  // not counted as clipping
}

}  // namespace
}  // namespace sonarsynth

namespace sonarsynth {
namespace {

// The whole sensor stage on each SIMD path (docs/physics.md §1.6), with the unfiltered and the
// range-filtered detector: AVX-512 and AVX2 give the same quantised samples; the scalar path
// differs by float rounding (< 2e-6 of a sample's power, sensor_kernel_test.cpp), so at most one
// count, on samples at a rounding edge.
TEST(SensorEffects, SimdPathsGiveTheSameSamplesOrOneCountApart) {
  const auto scene = scene_with(true);
  for (const bool filtered : {false, true}) {
    SimulationConfig c;  // every sensor effect at its default: texture, looks, noise, floor
    c.sonar.max_range_m = 30.0;
    c.sonar.samples_per_channel = 600;
    // A CW pulse of range window 12 cm over 5 cm samples: the range filter's taps.
    c.sonar.pulse = SonarConfig::Pulse::kCw;
    c.sonar.pulse_length_s = filtered ? 2.0 * 0.12 / c.sonar.sound_speed_m_s : 0.0;
    c.noise.range_correlation = filtered;
    c.threads = 1;
    const Simulator sim(scene, c, kAltitude);
    ASSERT_EQ(SensorModel::make(c, 1.0, kAltitude).range_taps.empty(), !filtered);
    std::vector<std::vector<float>> paths;
    for (const simd::Target t : simd::supported_targets()) {
      simd::set_target(t);
      const RenderedPing p = render(sim, pose_at(*scene, 0.0, 5));
      std::vector<float> all = p.port.samples;
      all.insert(all.end(), p.starboard.samples.begin(), p.starboard.samples.end());
      paths.push_back(all);
    }
    simd::set_target(simd::Target::automatic);
    ASSERT_GE(paths.size(), 1u);
    if (paths.size() == 3) {
      EXPECT_EQ(paths[1], paths[2]);
    }
    for (std::size_t k = 1; k < paths.size(); ++k) {
      std::size_t differ = 0;
      for (std::size_t i = 0; i < paths[0].size(); ++i) {
        ASSERT_LE(std::abs(paths[k][i] - paths[0][i]), 1.0f) << i;
        differ += paths[k][i] != paths[0][i] ? 1 : 0;
      }
      EXPECT_LT(differ, paths[0].size() / 50) << differ;
      std::printf("path %zu against the scalar path (%s): %zu of %zu samples one count apart\n", k,
                  filtered ? "filtered" : "unfiltered", differ, paths[0].size());
    }
  }
}

}  // namespace
}  // namespace sonarsynth
