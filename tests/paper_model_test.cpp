// SPDX-License-Identifier: MIT
// The founding paper's model through the Simulator (docs/paper-model.md): K = 1/Imax per ping
// (OutputScaling::Normalise::per_ping_max) and eq. (2) with the paper's gamma.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>
#include <vector>

#include "simulator_test_util.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {
namespace {

// A plane z = z0 + slope_x x on a `cell` m grid over [x0, x0 + size] x [y0, y0 + size].
Scene plane_scene(double x0, double y0, double size, double cell, double z0, double slope_x) {
  return test::make_scene(x0, y0, size, cell, [=](double x, double) { return z0 + slope_x * x; });
}

PingPose pose_at(const Scene& s, double x, double y, double altitude) {
  PingPose p;
  p.sensor_xy_m = {x, y};
  p.heading_rad = 0.0;  // north: starboard is east, where the plane rises
  p.sensor_z_m = s.bathymetry.height_m(x, y) + altitude;
  p.altitude_m = altitude;
  p.ping_index = 7;
  return p;
}

SimulationConfig paper_config() {
  SimulationConfig c;
  c.sonar.max_range_m = 40.0;
  c.sonar.samples_per_channel = 800;
  c.sonar.vertical_beam.shape = VerticalBeamShape::paper_sine_pair;
  c.sonar.vertical_beam.upper_half_width_rad = 25.0 * 3.14159265358979323846 / 180.0;
  c.sonar.vertical_beam.lower_half_width_rad = 30.0 * 3.14159265358979323846 / 180.0;
  c.physics.absorption = false;
  c.noise.model = NoiseConfig::Model::kNone;
  c.output.tvg = TvgLaw::spherical;
  c.output.round_to_integer = false;
  c.output.max_value = 1000.0;
  c.output.quantity = SampleQuantity::intensity;  // the paper's image is an intensity
  c.sensor = SensorConfig::none();
  c.quality.along_track_planes = 1;
  c.threads = 1;
  return c;
}

double max_of(const std::vector<float>& v) {
  return *std::max_element(v.begin(), v.end());
}

// K = 1/Imax: each ping is the globally calibrated ping times max_value / (its largest sample
// over both sides), whatever the gain; the brightest sample of every ping is the full scale.
TEST(PaperModel, PerPingMaxNormalisationIsKEqualsOneOverImax) {
  const Scene scene = plane_scene(-60, -60, 120, 0.5, -30.0, 0.1);
  SimulationConfig plain = paper_config();
  plain.output.gain_db = 0.0;
  plain.output.max_value = 1e30;  // no clamp: the calibrated samples themselves
  SimulationConfig norm = paper_config();
  norm.output.gain_db = 37.0;  // cancels
  norm.output.normalise = OutputScaling::Normalise::per_ping_max;
  norm.clean_samples = true;
  const Simulator a(scene, plain, 10.0), b(scene, norm, 10.0);
  auto wa = a.make_workspace(), wb = b.make_workspace();
  std::vector<double> maxima;
  // On a plane the TVG'd echo depends on the angles only (not the altitude): turning the track
  // along the slope changes the ping's maximum.
  for (const auto& [altitude, heading] :
       {std::pair{6.0, 0.0}, std::pair{17.0, 0.0}, std::pair{10.0, 0.5 * 3.14159265358979323846}}) {
    PingPose pose = pose_at(scene, 0.0, 0.0, altitude);
    pose.heading_rad = heading;
    RenderedPing pa, pb;
    a.render_ping(pose, *wa, pa);
    b.render_ping(pose, *wb, pb);
    const double imax = std::max(max_of(pa.port.samples), max_of(pa.starboard.samples));
    ASSERT_GT(imax, 0.0);
    maxima.push_back(imax);
    EXPECT_NEAR(std::max(max_of(pb.port.samples), max_of(pb.starboard.samples)), 1000.0, 1e-3);
    if (heading == 0.0) {
      // Starboard (the rising side) holds the maximum; port is below full scale.
      EXPECT_GT(max_of(pa.starboard.samples), max_of(pa.port.samples));
      EXPECT_LT(max_of(pb.port.samples), 1000.0);
    }
    for (const auto& [got, clean, ref] :
         {std::tuple{&pb.port.samples, &pb.port.clean_samples, &pa.port.samples},
          std::tuple{&pb.starboard.samples, &pb.starboard.clean_samples, &pa.starboard.samples}}) {
      for (std::size_t i = 0; i < ref->size(); ++i) {
        const double want = 1000.0 * (*ref)[i] / imax;
        EXPECT_NEAR((*got)[i], want, 1e-5 * 1000.0) << "altitude " << altitude << " sample " << i;
        EXPECT_EQ((*got)[i], (*clean)[i]);  // noise off: the clean samples are the same
      }
    }
  }
  // The calibrated maxima differ from ping to ping; the normalised ones do not.
  EXPECT_GT(std::abs(10.0 * std::log10(maxima[0] / maxima[2])), 1.0);
}

// Calls f(clean, noisy) for every sample of both sides of 20 pings rendered by a Simulator of
// `c` (x = 0, y = 0 ... 19 m, 10 m above the seabed; ping_index = y).
template <class F>
void for_each_sample(const Scene& scene, const SimulationConfig& c, F&& f) {
  const Simulator sim(scene, c, 10.0);
  auto ws = sim.make_workspace();
  for (std::uint64_t p = 0; p < 20; ++p) {
    PingPose pose = pose_at(scene, 0.0, static_cast<double>(p), 10.0);
    pose.ping_index = p;
    RenderedPing out;
    sim.render_ping(pose, *ws, out);
    for (const SideOutput* s : {&out.port, &out.starboard}) {
      for (std::size_t i = 0; i < s->samples.size(); ++i) f(s->clean_samples[i], s->samples[i]);
    }
  }
}

// Eq. (2) with the paper's gamma: u ~ U(0, sqrt(12 gamma)) multiplies the normalised image, so
// every lit sample is at least its clean value and at most (1 + sqrt(12 gamma)) times it, with
// E[1 + u] = 1 + sqrt(3 gamma); the Rayleigh term's mean is snr_db below full scale.
TEST(PaperModel, PaperNoiseWithGammaOnTheNormalisedImage) {
  const Scene scene = plane_scene(-60, -60, 120, 0.5, -30.0, 0.0);
  const double gamma = 0.03, g = std::sqrt(12.0 * gamma);
  SimulationConfig c = paper_config();
  c.output.normalise = OutputScaling::Normalise::per_ping_max;
  c.noise.model = NoiseConfig::Model::kPaper;
  c.noise.paper_uniform_variance = gamma;
  c.noise.snr_at_max_range_db = 200.0;  // Rayleigh term negligible here
  c.clean_samples = true;
  double sum = 0.0;
  std::size_t n = 0;
  for_each_sample(scene, c, [&](double clean, double noisy) {
    // Dark, or bright enough to be clamped at full scale (which would bias the mean).
    if (!(clean > 1.0) || clean * (1.0 + g) >= 1000.0) return;
    const double ratio = noisy / clean;
    EXPECT_GE(ratio, 1.0 - 1e-6);
    EXPECT_LE(ratio, 1.0 + g + 1e-6);
    sum += ratio;
    ++n;
  });
  ASSERT_GT(n, 10000u);
  EXPECT_NEAR(sum / static_cast<double>(n), 1.0 + 0.5 * g,
              4.0 * std::sqrt(gamma / static_cast<double>(n)));

  // The Rayleigh term alone (gamma = 0): its mean, sigma sqrt(pi/2), is snr_db below the full
  // scale; measured where the clean image is 0 (beyond the paper beam's lower edge).
  c.noise.paper_uniform_variance = 0.0;
  c.noise.snr_at_max_range_db = 20.0;
  double rsum = 0.0;
  std::size_t rn = 0;
  for_each_sample(scene, c, [&](double clean, double noisy) {
    if (clean != 0.0) return;
    rsum += noisy;
    ++rn;
  });
  ASSERT_GT(rn, 5000u);
  // Rayleigh mean 1000 / 100 = 10, standard deviation sqrt(4 / pi - 1) x 10.
  EXPECT_NEAR(rsum / static_cast<double>(rn), 10.0,
              4.0 * std::sqrt(4.0 / 3.14159265358979323846 - 1.0) * 10.0 /
                  std::sqrt(static_cast<double>(rn)));
}

}  // namespace
}  // namespace sonarsynth
