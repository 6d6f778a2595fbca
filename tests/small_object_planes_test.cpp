// SPDX-License-Identifier: MIT
// Objects narrower along the track than the beam planes' spacing (docs/physics.md §1.3): seen in
// every ping whose beam covers them, weighted by the horizontal pattern.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "simulator_test_util.hpp"
#include "sonarsynth/along_track_planes.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {
namespace {

using test::make_scene;
using test::plain_config;
using test::pose_at;

// Composite Simpson rule of SonarConfig::horizontal_two_way over [a, b] (independent of the
// closed form the library uses).
double pattern_integral(const SonarConfig& sonar, double a, double b) {
  constexpr int kIntervals = 4000;
  const double h = (b - a) / kIntervals;
  double sum = sonar.horizontal_two_way(a) + sonar.horizontal_two_way(b);
  for (int i = 1; i < kIntervals; ++i) {
    sum += (i % 2 != 0 ? 4.0 : 2.0) * sonar.horizontal_two_way(a + i * h);
  }
  return sum * h / 3.0;
}

TEST(SmallObjectPlanes, PatternIntegralMatchesSimpson) {
  SonarConfig sonar;
  sonar.horizontal_beam_width_rad = rad_from_deg(0.8);
  const double bw = sonar.horizontal_beam_width_rad;
  for (const auto& [a, b] : {std::pair{-1.25 * bw, 1.25 * bw}, std::pair{0.1 * bw, 0.13 * bw},
                             std::pair{-0.9 * bw, -0.2 * bw}}) {
    const double ref = pattern_integral(sonar, a, b);
    EXPECT_NEAR(horizontal_two_way_integral(bw, a, b), ref, 1e-12 * std::abs(ref) + 1e-18);
  }
}

// A 5 cm x 5 cm post 1 m tall, 30 m to starboard of a northbound line, pinged every 5 cm with
// a 1 deg beam (one base plane): its lit face's energy per ping must follow the horizontal
// pattern integrated over the azimuths it subtends.
class PostAcrossPings : public ::testing::Test {
 protected:
  static constexpr double kSpacing = 0.05, kPostX = 30.0, kHalf = 0.025;
  static constexpr int kPings = 41;  // y = -1 ... 1 m

  PostAcrossPings()
      : flat_(make_scene(-60, -60, 120, 0.5, [](double, double) { return -20.0; })), post_(flat_) {
    test::add_on_seabed(post_,
                        test::primitive(ObjectShape::kBox, 3, post_.materials.index_of("steel"),
                                        {kPostX, 0.0}, {kHalf, kHalf, 0.5}),
                        "post");
    cfg_ = plain_config();
    cfg_.sonar.samples_per_channel = 2000;  // 2 cm bins over 40 m
    cfg_.sonar.horizontal_beam_width_rad = rad_from_deg(1.0);
    cfg_.quality.along_track_planes = 1;
  }
  double y_of(int j) const { return -1.0 + kSpacing * j; }

  // Starboard side of every ping.
  std::vector<SideOutput> render(const Scene& scene, bool refine) const {
    SimulationConfig cfg = cfg_;
    cfg.quality.small_object_planes = refine;
    Simulator sim(scene, cfg, 10.0);
    auto ws = sim.make_workspace();
    std::vector<SideOutput> out;
    for (int j = 0; j < kPings; ++j) {
      RenderedPing p;
      sim.render_ping(pose_at(scene, {0.0, y_of(j)}, 0.0, 10.0), *ws, p);
      out.push_back(std::move(p.starboard));
    }
    return out;
  }

  // Energy of the post's front face and top: the bins from its top's range (31.30 m) to its
  // base's (31.60 m), minus the flat seabed's. The seabed in front of the post is lit in both;
  // the seabed it hides starts at 31.60 m (under it) and 31.65 m (behind it).
  static constexpr std::size_t kFirst = 1562, kLast = 1579;
  static double face_energy(const SideOutput& with, const SideOutput& flat) {
    double e = 0.0;
    for (std::size_t i = kFirst; i <= kLast; ++i) {
      e += double{with.samples[i]} - double{flat.samples[i]};
    }
    return e;
  }

  Scene flat_, post_;
  SimulationConfig cfg_;
};

TEST_F(PostAcrossPings, SeenInEveryPingOfItsFootprintWeightedByThePattern) {
  const auto flat = render(flat_, true), on = render(post_, true), off = render(post_, false);
  const SonarConfig& sonar = cfg_.sonar;
  const double fan = 1.25 * sonar.horizontal_beam_width_rad;
  // Without refinement one plane sees the post, in the one ping whose plane crosses it (y = 0),
  // with the whole strip's share: that is the face's energy per unit of beta_eff.
  const int centre = 20;
  const double e_strip = face_energy(off[centre], flat[centre]);
  ASSERT_GT(e_strip, 0.0);
  int off_pings = 0;
  for (int j = 0; j < kPings; ++j) off_pings += face_energy(off[j], flat[j]) > 1e-6 * e_strip;
  EXPECT_EQ(off_pings, 1);

  const double whole = pattern_integral(sonar, -fan, fan);
  std::vector<double> got(kPings), expected(kPings);
  for (int j = 0; j < kPings; ++j) {
    got[j] = face_energy(on[j], flat[j]);
    const double a = std::atan2(-kHalf - y_of(j), kPostX - kHalf);
    const double b = std::atan2(kHalf - y_of(j), kPostX - kHalf);
    const double lo = std::clamp(a, -fan, fan), hi = std::clamp(b, -fan, fan);
    expected[j] = e_strip * pattern_integral(sonar, lo, hi) / whole;
  }
  const double peak_expected = *std::max_element(expected.begin(), expected.end());
  const double peak_got = *std::max_element(got.begin(), got.end());
  double sum_got = 0.0, sum_expected = 0.0;
  int half_got = 0, half_expected = 0, seen = 0;
  double worst_db = 0.0;
  for (int j = 0; j < kPings; ++j) {
    seen += got[j] > 1e-3 * peak_got;
    sum_got += got[j];
    sum_expected += expected[j];
    half_got += got[j] >= 0.5 * peak_got;
    half_expected += expected[j] >= 0.5 * peak_expected;
    if (expected[j] >= 0.25 * peak_expected) {
      const double db = 10.0 * std::log10(got[j] / expected[j]);
      EXPECT_NEAR(db, 0.0, 0.5) << "ping y = " << y_of(j);
      worst_db = std::max(worst_db, std::abs(db));
    }
  }
  RecordProperty("pings_seen_above_minus30dB", seen);
  RecordProperty("pings_above_half_peak", half_got);
  RecordProperty("worst_db_within_6dB_of_peak", std::to_string(worst_db));
  RecordProperty("energy_sum_ratio", std::to_string(sum_got / sum_expected));
  RecordProperty("peak_vs_unrefined_db", std::to_string(10.0 * std::log10(peak_got / e_strip)));
  EXPECT_NEAR(sum_got / sum_expected, 1.0, 0.03);
  // The two-way -3 dB along-track footprint (1 / sqrt 2 deg at 30 m: 0.37 m) holds about seven
  // pings 5 cm apart.
  EXPECT_GE(half_expected, 7);
  EXPECT_NEAR(half_got, half_expected, 1);
  // The peak: the post's share of the pattern (its 1.7 mrad of 17.5), about 9 dB below the
  // single plane's whole strip.
  EXPECT_NEAR(10.0 * std::log10(peak_got / e_strip), 10.0 * std::log10(peak_expected / e_strip),
              0.5);
  EXPECT_LT(peak_got, 0.2 * e_strip);

  // Before the post's range every refined plane sees the flat seabed and the shares sum to
  // beta_eff: the refined ping equals the unrefined one there (to rounding: each plane's nadir,
  // at the altitude, falls on a bin edge up to an ulp either way).
  for (int j = 0; j < kPings; ++j) {
    const auto& a = on[j].samples;
    const auto& b = off[j].samples;
    const double top = *std::max_element(b.begin(), b.end());
    for (std::size_t i = 0; i < 1550; ++i) ASSERT_NEAR(a[i], b[i], 1e-7 * top) << j << " " << i;
  }
}

TEST_F(PostAcrossPings, LabelledWhereItHoldsMostOfTheEnergy) {
  // The truth names the post in a sample where it holds more than half of the energy, whichever
  // plane sees it. Independently: the post's energy in a face bin is the difference from the
  // flat seabed, whose echo there (the seabed in front of the post) the post leaves unchanged.
  const auto flat = render(flat_, true), on = render(post_, true), off = render(post_, false);
  int labelled_on = 0, labelled_off = 0;
  for (int j = 0; j < kPings; ++j) {
    const auto has_post = [](const SideOutput& s) {
      return std::find(s.truth_label.begin(), s.truth_label.end(), 3) != s.truth_label.end();
    };
    bool dominant = false, minor = true;  // some face bin over 3x / every one under 1.5x
    for (std::size_t i = kFirst; i <= kLast; ++i) {
      const double ratio = double{on[j].samples[i]} / double{flat[j].samples[i]};
      dominant = dominant || ratio > 3.0;
      minor = minor && ratio < 1.5;
    }
    const bool labelled = has_post(on[j]);
    if (dominant) {
      EXPECT_TRUE(labelled) << "ping y = " << y_of(j);
    }
    if (minor) {
      EXPECT_FALSE(labelled) << "ping y = " << y_of(j);
    }
    labelled_on += labelled;
    labelled_off += has_post(off[j]);
  }
  EXPECT_GE(labelled_on, 5);
  EXPECT_EQ(labelled_off, 1);  // the central plane alone: the ping at y = 0
  RecordProperty("pings_labelled", labelled_on);
}

TEST(SmallObjectPlanes, RefinesOnlyTheSidesThatSeeANarrowObjectInRange) {
  SonarConfig sonar;
  sonar.horizontal_beam_width_rad = rad_from_deg(1.0);
  const double beta = sonar.beta_eff_rad();
  const AlongTrackPlanes base = make_along_track_planes(sonar, 3, beta);
  ObjectSet objects;
  ObjectPrimitive narrow;  // 5 cm post at (30, 0)
  narrow.shape = ObjectShape::kBox;
  narrow.centre_xy_m = {30.0, 0.0};
  narrow.half_extent_m = {0.025, 0.025, 0.5};
  objects.add(narrow);
  ObjectPrimitive wide = narrow;  // 4 m along the track at (-30, 0): the base planes see it
  wide.id = 2;
  wide.centre_xy_m = {-30.0, 0.0};
  wide.half_extent_m = {2.0, 0.025, 0.5};
  objects.add(wide);
  objects.build_index();
  const ObjectPlaneRefiner refiner(objects, sonar, base, beta);
  AlongTrackPlanes out;
  std::vector<double> scratch;
  const Eigen::Vector2d east(1.0, 0.0), west(-1.0, 0.0);
  EXPECT_FALSE(refiner.refine({0.0, 0.0}, west, 40.0, out, scratch));  // the wide object
  EXPECT_FALSE(refiner.refine({0.0, 0.0}, east, 25.0, out, scratch));  // post out of range
  EXPECT_FALSE(refiner.refine({0.0, 5.0}, east, 40.0, out, scratch));  // post outside the fan
  ASSERT_TRUE(refiner.refine({0.0, 0.2}, east, 40.0, out, scratch));
  // The shares sum to beta_eff, the azimuths are sorted inside the fan, the central one is 0,
  // and at least kPlanesPerObject planes cross the post's azimuth interval.
  double sum = 0.0;
  for (double w : out.beta_eff_rad) sum += w;
  EXPECT_NEAR(sum, beta, 1e-15);
  EXPECT_TRUE(std::is_sorted(out.azimuth_rad.begin(), out.azimuth_rad.end()));
  EXPECT_EQ(out.azimuth_rad[out.central], 0.0);
  EXPECT_LE(out.azimuth_rad.back(), 1.25 * sonar.horizontal_beam_width_rad);
  const double a = std::atan2(-0.225, 29.975), b = std::atan2(-0.175, 29.975);
  const auto inside = std::count_if(out.azimuth_rad.begin(), out.azimuth_rad.end(),
                                    [&](double psi) { return psi > a && psi < b; });
  EXPECT_GE(inside, ObjectPlaneRefiner::kPlanesPerObject);
}

}  // namespace
}  // namespace sonarsynth
