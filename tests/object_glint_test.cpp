// SPDX-License-Identifier: MIT
// Object glints and the built-in object surfaces (docs/physics.md §1.11): the Kirchhoff lobe of
// a facet against its closed form (a box face at normal incidence, integrated independently in
// tan theta), nothing changed when it is off, the paper model's scaling, the texture of the
// built-in steel against its Gamma law, and glints that vary from ping to ping with the
// roughness of the surface.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "simulator_test_util.hpp"
#include "sonarsynth/backscatter.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/render_side.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {
namespace {

using namespace test;  // the Simulator tests' scenes and configurations

constexpr double kBeta = 0.02;
constexpr double kY = 10.0;  // the face's across-track distance, metres (sensor at z = 0)
constexpr double kRho = 0.3, kS = 0.1, kMu = 0.01;

TEST(KirchhoffLobe, ClosedForm) {
  const KirchhoffLobe lobe = KirchhoffLobe::make(kRho, kS);
  EXPECT_DOUBLE_EQ(lobe.sigma(1.0), kRho / (8.0 * kS * kS));
  for (double theta : {0.05, 0.1, 0.2, 0.3}) {
    const double c = std::cos(theta), t = std::tan(theta);
    const double expected =
        kRho / (8.0 * kS * kS * std::pow(c, 4)) * std::exp(-t * t / (2.0 * kS * kS));
    EXPECT_NEAR(lobe.sigma(c), expected, 1e-13 * lobe.peak) << theta;
  }
  EXPECT_EQ(lobe.sigma(0.0), 0.0);
  EXPECT_EQ(lobe.sigma(-0.5), 0.0);
  // Cut where sigma < e^-40 of the peak (tan^2 = 80 s^2).
  EXPECT_EQ(lobe.sigma(std::cos(std::atan(std::sqrt(81.0) * kS))), 0.0);
}

SideParams face_params(bool glints, double rho = kRho) {
  SideParams p;
  p.sample_spacing_m = 0.001;
  p.samples = 10600;
  p.beta_eff_rad = kBeta;
  p.vertical_beam.shape = VerticalBeamShape::uniform;
  p.backscatter = BackscatterModel::lambert;
  p.materials = {Material{.name = "seabed"}, Material{.name = "plate",
                                                      .lambert_mu = kMu,
                                                      .paper_reflectivity = 0.4,
                                                      .specular_rho = rho,
                                                      .specular_rms_slope = kS}};
  p.object_glints = glints;
  p.gauss_points = 3;
  return p;
}

// A box 2 m high and 0.5 m deep in mid-water, its face towards the sensor at y = kY from
// z = -1 to 1 (the sensor at z = 0 sees it at normal incidence at z = 0); the seabed 100 m down.
BeamProfile face_profile() {
  BeamProfile p;
  p.sensor_z_m = 0.0;
  p.add_node(0.0, -100.0);
  p.add_node(200.0, -100.0);
  const double ys[] = {kY, kY, kY + 0.5, kY + 0.5}, zs[] = {-1.0, 1.0, 1.0, -1.0};
  p.add_section(ys, zs, 4, 3, 1);
  return p;
}

// Specular energy of the face in [r1, r2): with u = tan theta = z / Y, r = Y sqrt(1 + u^2) and
// dz = Y du, K beta sigma_s r^-3 dz = K beta rho / (8 s^2 Y^2) sqrt(1 + u^2) exp(-u^2 / (2 s^2))
// du, twice (z > 0 and z < 0); midpoint rule in u.
double specular_bin(double r1, double r2) {
  const auto u_of = [](double r) { return r > kY ? std::sqrt((r / kY) * (r / kY) - 1.0) : 0.0; };
  const double u0 = u_of(r1), u1 = std::min(u_of(r2), 1.0 / kY);
  if (!(u1 > u0)) return 0.0;
  const int n = 20000;
  const double h = (u1 - u0) / n;
  double sum = 0.0;
  for (int k = 0; k < n; ++k) {
    const double u = u0 + (k + 0.5) * h;
    sum += std::sqrt(1.0 + u * u) * std::exp(-u * u / (2.0 * kS * kS));
  }
  return 2.0 * kBeta * kRho / (8.0 * kS * kS * kY * kY) * sum * h;
}

TEST(ObjectGlint, BoxFaceAtNormalIncidenceAgainstTheClosedForm) {
  const BeamProfile prof = face_profile();
  SideEcho on, off;
  render_side(prof, face_params(true), on);
  render_side(prof, face_params(false), off);
  const double dr = 0.001;
  double peak = 0.0, total = 0.0, expected_total = 0.0;
  std::vector<double> expected(on.intensity.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const double r1 = dr * static_cast<double>(i);
    expected[i] = specular_bin(r1, r1 + dr);
    peak = std::max(peak, expected[i]);
  }
  ASSERT_GT(peak, 0.0);
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const double spec = on.intensity[i] - off.intensity[i];
    EXPECT_NEAR(spec, expected[i], 1e-6 * peak) << "bin " << i;
    total += spec;
    expected_total += expected[i];
  }
  EXPECT_NEAR(total / expected_total, 1.0, 1e-6);
  // The level at normal incidence: the first bin [Y, Y + dr) spans u in [0, U0], where
  // sqrt(1 + u^2) exp(-u^2 / (2 s^2)) = 1 - u^2 (1 / s^2 - 1) / 2 + O(u^4): its energy is
  // 2 K beta sigma_s(0) U0 / Y^2 (1 - U0^2 (1 / s^2 - 1) / 6), sigma_s(0) = rho / (8 s^2).
  const std::size_t first = static_cast<std::size_t>(std::floor(kY / dr));
  const double u0 = std::sqrt((1.0 + dr / kY) * (1.0 + dr / kY) - 1.0);
  const double level = 2.0 * kBeta * kRho / (8.0 * kS * kS) * u0 / (kY * kY) *
                       (1.0 - u0 * u0 * (1.0 / (kS * kS) - 1.0) / 6.0);
  EXPECT_NEAR((on.intensity[first] - off.intensity[first]) / level, 1.0, 1e-3);
  // The glint outshines the face's Lambert return there: rho / (8 s^2) = 3.75 against mu = 0.01.
  EXPECT_GT(on.intensity[first], 100.0 * off.intensity[first]);
}

TEST(ObjectGlint, OffLeavesTheRenderBitIdentical) {
  const BeamProfile prof = face_profile();
  SideEcho none, off, no_lobe;
  render_side(prof, face_params(false, 0.0), none);
  render_side(prof, face_params(false), off);          // a lobe, switched off
  render_side(prof, face_params(true, 0.0), no_lobe);  // switched on, no lobe
  EXPECT_EQ(off.intensity, none.intensity);
  EXPECT_EQ(no_lobe.intensity, none.intensity);
}

TEST(ObjectGlint, PaperModelScalesTheLobeAsTheDiffuseTerm) {
  const BeamProfile prof = face_profile();
  SideParams lam_on = face_params(true), lam_off = face_params(false);
  SideParams pap_on = lam_on, pap_off = lam_off;
  pap_on.backscatter = pap_off.backscatter = BackscatterModel::paper;
  SideEcho a, b, c, d;
  render_side(prof, lam_on, a);
  render_side(prof, lam_off, b);
  render_side(prof, pap_on, c);
  render_side(prof, pap_off, d);
  const double ratio = 0.4 / kMu;  // R / mu
  double peak = 0.0;
  for (std::size_t i = 0; i < a.intensity.size(); ++i) peak = std::max(peak, a.intensity[i]);
  for (std::size_t i = 0; i < a.intensity.size(); ++i) {
    EXPECT_NEAR(c.intensity[i], ratio * a.intensity[i], 1e-9 * ratio * peak) << i;
    EXPECT_NEAR(d.intensity[i], ratio * b.intensity[i], 1e-9 * ratio * peak) << i;
  }
}

TEST(ObjectMaterials, BuiltInSteelAndConcreteHaveSurfaces) {
  const MaterialTable t = MaterialTable::defaults();
  const Material& steel = t[t.index_of("steel")];
  const Material& concrete = t[t.index_of("concrete")];
  EXPECT_EQ(steel.texture_shape_nu, 10.0);
  EXPECT_EQ(steel.roughness_rms_m, 0.01);
  EXPECT_EQ(steel.roughness_length_m, 0.3);
  EXPECT_NEAR(10.0 * std::log10(steel.specular_rho), -5.5, 1e-12);
  EXPECT_EQ(steel.specular_rms_slope, 0.1);
  EXPECT_EQ(concrete.texture_shape_nu, 5.0);
  EXPECT_EQ(concrete.roughness_rms_m, 0.01);
  EXPECT_EQ(concrete.roughness_length_m, 0.2);
  EXPECT_NEAR(10.0 * std::log10(concrete.specular_rho), -8.0, 1e-12);
  EXPECT_EQ(concrete.specular_rms_slope, 0.15);
  for (const char* seabed : {"mud", "sand", "gravel", "rock"}) {
    EXPECT_EQ(t[t.index_of(seabed)].specular_rho, 0.0) << seabed;
  }
  Material bad = steel;
  bad.specular_rho = 1.5;
  EXPECT_THROW(bad.validate(), InputError);
  bad = steel;
  bad.specular_rms_slope = 0.0;
  EXPECT_THROW(bad.validate(), InputError);
}

// A flat seabed 20 m deep and a box of the built-in `material`, 2 m high, 10 m across (x 10 to
// 20 m) and 30 m along the track; `smooth` takes its roughness off.
Scene box_scene(const char* material, bool smooth) {
  Scene scene = make_scene(-40, -40, 80, 1.0, [](double, double) { return -20.0; });
  if (smooth) {
    Material m = scene.materials[scene.materials.index_of(material)];
    m.roughness_rms_m = 0.0;
    scene.materials.set(m);
  }
  const std::uint16_t index = scene.materials.index_of(material);
  return with_test_box(std::move(scene), index);
}

TEST(ObjectMaterials, BuiltInSteelTextureFollowsItsGammaLaw) {
  // The textured over the untextured single-look intensity (same speckle keys) on the box: the
  // texture T ~ Gamma(10, 1/10): mean 1, variance 1/10, P(T < 1/2) = 1 - e^-5 sum_{k<10} 5^k/k!.
  const Scene scene = box_scene("steel", false);
  const Simulator with(scene, speckle_config(true), 10.0),
      without(scene, speckle_config(false), 10.0);
  auto wa = with.make_workspace(), wb = without.make_workspace();
  double n = 0.0, sum = 0.0, sum2 = 0.0, below_half = 0.0;
  for (int k = 0; k < 100; ++k) {
    PingPose pose = pose_at(scene, {0.0, -10.0 + 0.2 * k}, 0.0, 10.0);
    pose.ping_index = static_cast<std::uint64_t>(k);
    RenderedPing a, b;
    with.render_ping(pose, *wa, a);
    without.render_ping(pose, *wb, b);
    for (std::size_t i = 0; i < a.starboard.samples.size(); ++i) {
      if (a.starboard.truth_class[i] != SampleClass::object || !(b.starboard.samples[i] > 0.0f)) {
        continue;
      }
      const double t = static_cast<double>(a.starboard.samples[i]) / b.starboard.samples[i];
      n += 1.0;
      sum += t;
      sum2 += t * t;
      below_half += t < 0.5 ? 1.0 : 0.0;
    }
  }
  ASSERT_GT(n, 10000.0);
  double term = 1.0, partial = 0.0;
  for (int k = 0; k < 10; ++k) {
    partial += term;
    term *= 5.0 / (k + 1);
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, 1.0, 0.02);
  EXPECT_NEAR(sum2 / n - mean * mean, 0.1, 0.01);
  EXPECT_NEAR(below_half / n, 1.0 - std::exp(-5.0) * partial, 0.01);  // 0.0293
}

// The brightest object sample of the starboard side in each of `pings` pings 0.1 m apart, the
// sensor 2.5 m above the seabed (half a metre above the box).
std::vector<double> object_peaks(const Scene& scene, bool glints, int pings) {
  SimulationConfig c = plain_config();
  c.physics.object_glints = glints;
  const Simulator sim(scene, c, 10.0);
  auto ws = sim.make_workspace();
  std::vector<double> peaks;
  for (int k = 0; k < pings; ++k) {
    RenderedPing p;
    sim.render_ping(pose_at(scene, {0.0, -5.0 + 0.1 * k}, 0.0, 2.5), *ws, p);
    double peak = 0.0;
    for (std::size_t i = 0; i < p.starboard.samples.size(); ++i) {
      if (p.starboard.truth_class[i] == SampleClass::object) {
        peak = std::max(peak, static_cast<double>(p.starboard.samples[i]));
      }
    }
    peaks.push_back(peak);
  }
  return peaks;
}

double coefficient_of_variation(const std::vector<double>& v) {
  double s = 0.0, s2 = 0.0;
  for (double x : v) {
    s += x;
    s2 += x * x;
  }
  const double n = static_cast<double>(v.size()), m = s / n;
  return std::sqrt(std::max(0.0, s2 / n - m * m)) / m;
}

TEST(ObjectGlint, VariesFromPingToPingWithTheRoughness) {
  // The box's near wall, 10 m away, is seen 3 to 14 deg from its normal: it glints near its top.
  // The resolved roughness tilts its facets by ~ sigma / L, so the glint moves and flickers as
  // the beam plane moves along the box; a smooth box gives the same ping every time.
  const std::vector<double> smooth = object_peaks(box_scene("steel", true), true, 40);
  const std::vector<double> rough = object_peaks(box_scene("steel", false), true, 40);
  const std::vector<double> rough_no_glint = object_peaks(box_scene("steel", false), false, 40);
  EXPECT_LT(coefficient_of_variation(smooth), 1e-9);
  // The glint is ~12 dB above the wall's diffuse peak, and flickers more than it: a coefficient
  // of variation of ~0.2 against ~0.1, about 3 dB from the dimmest to the brightest ping.
  EXPECT_GT(rough[0], 5.0 * rough_no_glint[0]);
  EXPECT_GT(coefficient_of_variation(rough), 0.15);
  EXPECT_GT(coefficient_of_variation(rough), 1.5 * coefficient_of_variation(rough_no_glint));
  EXPECT_GT(
      *std::max_element(rough.begin(), rough.end()) / *std::min_element(rough.begin(), rough.end()),
      1.8);
}

}  // namespace
}  // namespace sonarsynth
