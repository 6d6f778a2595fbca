// SPDX-License-Identifier: MIT
// Second-order statistics of the sensor stage (docs/physics.md §1.6 and §1.10): speckle
// correlated in range by the pulse's matched-filter response, along the track by the translated
// aperture, the TVG law's shape of the volume reverberation and shadow fill, and the patch
// textures of both; each against a closed form computed here independently.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "simulator_test_util.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {
namespace {

constexpr double kSeabedZ = -30.0;
constexpr double kAltitude = 10.0;
constexpr std::size_t kSamples = 600;

// A flat sand seabed 30 m deep; with `wall`, a 6 m high ridge 8-10 m east of x = 0.
std::shared_ptr<const Scene> flat_scene(bool wall = false) {
  return std::make_shared<Scene>(test::make_scene(-60.0, -60.0, 120.0, 0.5, [&](double x, double) {
    return wall && x >= 8.0 && x <= 10.0 ? kSeabedZ + 6.0 : kSeabedZ;
  }));
}

// Intensity, one look, no thermal noise, no sensor terms: noisy over clean samples is the
// speckle field itself.
SimulationConfig speckle_config() {
  SimulationConfig c;
  c.sonar.max_range_m = 30.0;
  c.sonar.samples_per_channel = kSamples;  // dr = 5 cm
  c.quality.along_track_planes = 1;
  c.noise.texture = false;
  c.noise.snr_at_max_range_db = 300.0;
  c.sensor = SensorConfig::none();
  c.output.quantity = SampleQuantity::intensity;
  c.output.detector_sub_samples = 1;
  c.output.round_to_integer = false;
  c.clean_samples = true;
  c.threads = 1;
  return c;
}

// The speckle field (noisy / clean, starboard) of `pings` pings `spacing` apart along a
// north-south track.
std::vector<std::vector<double>> speckle_field(const Scene& scene, const SimulationConfig& c,
                                               int pings, double spacing) {
  const Simulator sim(std::shared_ptr<const Scene>(&scene, [](const Scene*) {}), c, kAltitude);
  auto ws = sim.make_workspace();
  std::vector<std::vector<double>> field;
  for (int k = 0; k < pings; ++k) {
    PingPose pose = sensor_pose(Eigen::Vector3d(0.0, -30.0 + spacing * k, kSeabedZ + kAltitude),
                                0.0, 0.0, 0.0, scene.bathymetry, static_cast<std::uint64_t>(k));
    pose.along_track_m = spacing * k;
    RenderedPing p;
    sim.render_ping(pose, *ws, p);
    std::vector<double> f(kSamples, 0.0);
    for (std::size_t i = 0; i < kSamples; ++i) {
      const double clean = p.starboard.clean_samples[i];
      f[i] = clean > 0.0 ? double{p.starboard.samples[i]} / clean : 0.0;
    }
    field.push_back(std::move(f));
  }
  return field;
}

struct Pearson {
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0, n = 0;
  void add(double x, double y) {
    sx += x, sy += y, sxx += x * x, syy += y * y, sxy += x * y, n += 1;
  }
  double r() const {
    const double cov = sxy / n - sx / n * sy / n;
    return cov / std::sqrt((sxx / n - sx * sx / n / n) * (syy / n - sy * sy / n / n));
  }
};

// Correlation of samples `lag` apart in range over samples [i0, i1) of every ping.
double range_lag(const std::vector<std::vector<double>>& f, std::size_t lag, std::size_t i0,
                 std::size_t i1) {
  Pearson p;
  for (const auto& row : f) {
    for (std::size_t i = i0; i + lag < i1; ++i) p.add(row[i], row[i + lag]);
  }
  return p.r();
}

// Correlation of consecutive pings over samples [i0, i1).
double ping_lag(const std::vector<std::vector<double>>& f, std::size_t i0, std::size_t i1) {
  Pearson p;
  for (std::size_t k = 0; k + 1 < f.size(); ++k) {
    for (std::size_t i = i0; i < i1; ++i) p.add(f[k][i], f[k + 1][i]);
  }
  return p.r();
}

TEST(SensorCorrelation, RangeFilterCorrelatesSamplesAsThePulsesMatchedFilter) {
  const auto scene = flat_scene();
  SimulationConfig c = speckle_config();
  c.sonar.pulse = SonarConfig::Pulse::kCw;
  c.sonar.pulse_length_s = 2.0 * 0.08 / c.sonar.sound_speed_m_s;  // range window W = 8 cm
  const double dr = c.sonar.sample_spacing_m(), w = 0.08;
  // The complex kernel: a triangle of half-width W integrated over each sample's cell (here by
  // a 2000-point midpoint rule); the intensity of a filtered circular Gaussian field correlates
  // at lag m as (sum h_k h_{k+m})^2 / (sum h_k^2)^2.
  std::vector<double> h;
  for (int k = -3; k <= 3; ++k) {
    double s = 0.0;
    for (int q = 0; q < 2000; ++q) {
      const double x = (k - 0.5 + (q + 0.5) / 2000.0) * dr;
      s += std::max(0.0, 1.0 - std::abs(x) / w);
    }
    h.push_back(s / 2000.0);
  }
  auto expected = [&](std::size_t m) {
    double num = 0.0, den = 0.0;
    for (std::size_t k = 0; k < h.size(); ++k) {
      den += h[k] * h[k];
      if (k + m < h.size()) num += h[k] * h[k + m];
    }
    return (num / den) * (num / den);
  };
  const auto f = speckle_field(*scene, c, 150, 0.5);
  EXPECT_NEAR(range_lag(f, 1, 240, 580), expected(1), 0.03);  // 0.58
  EXPECT_NEAR(range_lag(f, 2, 240, 580), expected(2), 0.03);  // 0.10
  EXPECT_GT(expected(1), 0.4);
  // The filter keeps the mean power (unit power gain).
  double sum = 0.0, n = 0.0;
  for (const auto& row : f) {
    for (std::size_t i = 240; i < 580; ++i) sum += row[i], n += 1;
  }
  EXPECT_NEAR(sum / n, 1.0, 0.03);
  // Off: independent samples.
  c.noise.range_correlation = false;
  const auto g = speckle_field(*scene, c, 150, 0.5);
  EXPECT_LT(std::abs(range_lag(g, 1, 240, 580)), 0.03);
}

TEST(SensorCorrelation, TranslatedApertureCorrelatesPingsAtEveryRange) {
  // Array length D = 0.886 lambda / theta; the lattice width sw, 1 / sw^2 = 24 / D^2 +
  // 1 / (sw_far^2 + D^2) with sw_far = r theta / sqrt(8 ln 2): pings d apart correlate in
  // intensity as exp(-d^2 / (2 sw^2)), nearly the same at 12.5 m and at 27.5 m.
  const auto scene = flat_scene();
  SimulationConfig c = speckle_config();
  const double d = 0.04;
  const double big_d = c.sonar.array_length_m();
  EXPECT_NEAR(big_d, 0.886 * (1500.0 / 400e3) / (3.14159265358979 / 180.0), 1e-9);
  const auto f = speckle_field(*scene, c, 300, d);
  const double dr = c.sonar.sample_spacing_m(), theta = c.sonar.horizontal_beam_width_rad;
  for (const std::size_t i0 : {std::size_t{240}, std::size_t{540}}) {
    const double r = (static_cast<double>(i0) + 20.0) * dr;
    const double far = r * theta / std::sqrt(8.0 * std::log(2.0));
    const double sw2 = 1.0 / (24.0 / (big_d * big_d) + 1.0 / (far * far + big_d * big_d));
    const double expected = std::exp(-d * d / (2.0 * sw2));
    EXPECT_NEAR(ping_lag(f, i0, i0 + 40), expected, 0.05) << "r = " << r;
  }
  // The far-field footprint alone (sw = sw_far): exp(-d^2 / (2 sw_far^2)), 0.91 at 12.5 m where
  // the translated aperture gives 0.58.
  c.noise.aperture_translation = false;
  const auto g = speckle_field(*scene, c, 300, d);
  for (const std::size_t i0 : {std::size_t{240}, std::size_t{540}}) {
    const double r = (static_cast<double>(i0) + 20.0) * dr;
    const double far = r * theta / std::sqrt(8.0 * std::log(2.0));
    EXPECT_NEAR(ping_lag(g, i0, i0 + 40), std::exp(-d * d / (2.0 * far * far)), 0.05)
        << "r = " << r;
  }
  EXPECT_GT(ping_lag(g, 240, 280) - ping_lag(f, 240, 280), 0.2);
}

TEST(SensorCorrelation, TvgLawShapesVolumeReverberationAndShadowFill) {
  // No speckle: the samples are the mean terms. With 20 log R + 2 alpha R the volume
  // reverberation (r^-2 before the TVG) is flat, and the fill falls as the seabed does, as
  // (r_mid / r) from its level at mid range; the seabed itself falls by 10 dB per decade.
  const auto scene = flat_scene(true);
  SimulationConfig c = speckle_config();
  c.noise.model = NoiseConfig::Model::kNone;
  c.clean_samples = false;
  c.sensor.volume_reverberation_db = -40.0;
  c.sensor.shadow_fill_db = -24.0;
  c.output.tvg_spreading_db_per_decade = 20.0;
  const Simulator sim(scene, c, kAltitude);
  auto ws = sim.make_workspace();
  RenderedPing p;
  sim.render_ping(sensor_pose(Eigen::Vector3d(0.0, 0.0, kSeabedZ + kAltitude), 0.0, 0.0, 0.0,
                              scene->bathymetry, 1),
                  *ws, p);
  const double ref = c.output.max_value * std::pow(10.0, c.output.seabed_median_dbfs / 10.0);
  const double dr = c.sonar.sample_spacing_m();
  std::size_t water = 0, shadow = 0;
  for (std::size_t i = 0; i < kSamples; ++i) {
    const double r = (static_cast<double>(i) + 0.5) * dr;
    const double volume = ref * 1e-4;
    const SampleClass cls = p.starboard.truth_class[i];
    if (cls == SampleClass::water_column && r < kAltitude - dr) {
      EXPECT_NEAR(p.starboard.samples[i], volume, 1e-5 * volume) << i;
      ++water;
    } else if (cls == SampleClass::shadow) {
      const double fill = ref * std::pow(10.0, -2.4) * (15.0 / r);
      EXPECT_NEAR(p.starboard.samples[i], fill + volume, 1e-5 * (fill + volume)) << i;
      ++shadow;
    }
  }
  EXPECT_GT(water, 150u);
  EXPECT_GT(shadow, 50u);
}

TEST(SensorCorrelation, PatchTexturesAreUnitMeanGammaOnPatches) {
  // No speckle, volume reverberation only (flat after 20 log R): each water-column sample is the
  // volume level times the patch texture, independent unit-mean Gamma(nu) values at the patch
  // nodes interpolated bilinearly (along the track and in range). Over positions uniform between
  // nodes the variance is ((2/3) / nu) (2/3) (E[(1 - w)^2 + w^2] = 2/3 per direction); in range,
  // samples dr apart at a node spacing p correlate as the linear interpolation's
  // autocorrelation, 1 - (3/2) x^2 + (3/4) x^3 at x = dr / p (p >= dr): 0.906 at x = 1/4.
  const auto scene = flat_scene();
  SimulationConfig c = speckle_config();
  c.noise.model = NoiseConfig::Model::kNone;
  c.clean_samples = false;
  c.sensor.volume_reverberation_db = -40.0;
  c.sensor.volume_texture_shape = 0.5;
  c.sensor.volume_patch_along_track_m = 0.5;
  c.sensor.volume_patch_range_m = 0.2;
  c.output.tvg_spreading_db_per_decade = 20.0;
  const Simulator sim(scene, c, kAltitude);
  auto ws = sim.make_workspace();
  const double ref = c.output.max_value * std::pow(10.0, c.output.seabed_median_dbfs / 10.0);
  const double dr = c.sonar.sample_spacing_m();
  double sum = 0.0, sum2 = 0.0, n = 0.0;
  Pearson adjacent;
  for (int k = 0; k < 1000; ++k) {
    PingPose pose = sensor_pose(Eigen::Vector3d(0.0, -40.0 + 0.1 * k, kSeabedZ + kAltitude), 0.0,
                                0.0, 0.0, scene->bathymetry, static_cast<std::uint64_t>(k));
    pose.along_track_m = 0.1 * k + 0.05;
    RenderedPing p;
    sim.render_ping(pose, *ws, p);
    for (std::size_t i = 0; i + 1 < kSamples; ++i) {
      const double r = (static_cast<double>(i) + 0.5) * dr;
      if (p.starboard.truth_class[i + 1] != SampleClass::water_column || r > kAltitude - 0.2) {
        continue;
      }
      const double t = p.starboard.samples[i] / (ref * 1e-4);
      const double t_next = p.starboard.samples[i + 1] / (ref * 1e-4);
      sum += t, sum2 += t * t, n += 1;
      adjacent.add(t, t_next);
    }
  }
  const double mean = sum / n, var = sum2 / n - mean * mean;
  const double expected_var = (2.0 / 3.0) * (2.0 / 3.0) / 0.5;
  EXPECT_NEAR(mean, 1.0, 0.06);
  EXPECT_NEAR(var, expected_var, 0.25 * expected_var);
  const double x = dr / 0.2;
  EXPECT_NEAR(adjacent.r(), 1.0 - 1.5 * x * x + 0.75 * x * x * x, 0.03);
}

}  // namespace
}  // namespace sonarsynth
