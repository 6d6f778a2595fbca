// SPDX-License-Identifier: MIT
// Shadow attribution (docs/labels.md "Shadow attribution"): the renderer records in the truth
// label of every shadow sample what hides it (the nearest object on the sample's ray from the
// sensor, 0 where only seabed relief does), and the instance rasters follow it. Checked against
// the analytic shadows of docs/physics.md §3.6 (box: ground length h y_b / (H - h)) and §3.15
// (a body off the seabed: the landing ranges of its tangent rays), worked out here from the
// geometry alone.
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "label_check_util.hpp"
#include "scene_test_util.hpp"
#include "sonarsynth/beam_profile.hpp"
#include "sonarsynth/formats/config/run_simulation.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"
#include "sonarsynth/formats/products/truth_labels.hpp"
#include "sonarsynth/render_side.hpp"
#include "sonarsynth/scene_object.hpp"
#include "sonarsynth/survey.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

SideParams params(double dr, std::size_t samples) {
  SideParams p;
  p.sample_spacing_m = dr;
  p.samples = samples;
  p.beta_eff_rad = 0.02;
  p.vertical_beam.shape = VerticalBeamShape::uniform;
  p.materials = {Material{.name = "test"}};
  p.materials[0].lambert_mu = 0.01;
  p.truth = true;
  return p;
}

// Flat seabed (z = 0) nodes every dy over (from, to], appended to `p`.
void add_flat(BeamProfile& p, double from, double to, double dy) {
  for (double y = from + dy; y <= to + 1e-9; y += dy) p.add_node(y, 0.0);
}

// A box of height h over ground [y_f, y_b] in the height profile, label `id`, on a flat seabed
// to y_max; sensor at height H.
BeamProfile profile_box(double H, double h, double y_f, double y_b, double y_max, std::int32_t id) {
  BeamProfile p;
  p.sensor_z_m = H;
  p.add_node(0.0, 0.0);
  add_flat(p, 0.0, y_f - 0.1, 0.1);
  p.add_node(y_f, 0.0);
  p.add_node(y_f, h, id);
  p.add_node(y_b, h, id);
  p.add_node(y_b, 0.0, id);
  add_flat(p, y_b, y_max, 0.1);
  return p;
}

// The same box as a closed section resting on the seabed (its bottom 5 cm in it).
void add_box_section(BeamProfile& p, double h, double y_f, double y_b, std::int32_t id) {
  const double ys[] = {y_f, y_f, y_b, y_b};
  const double zs[] = {-0.05, h, h, -0.05};  // clockwise in (y, z): the solid on the right
  p.add_section(ys, zs, 4, id, 0);
}

BeamProfile flat_profile(double H, double y_max) {
  BeamProfile p;
  p.sensor_z_m = H;
  p.add_node(0.0, 0.0);
  add_flat(p, 0.0, y_max, 0.1);
  return p;
}

// Sample i covers the slant ranges [i dr, (i + 1) dr) (no pulse window).
struct Samples {
  double dr;
  std::size_t first_inside(double r) const { return static_cast<std::size_t>(std::ceil(r / dr)); }
  std::size_t last_inside(double r) const {
    return static_cast<std::size_t>(std::floor(r / dr)) - 1;
  }
};

std::vector<std::uint32_t> instances(const SideEcho& e) {
  std::vector<std::uint32_t> out;
  labels::side_instances(e.truth_class, e.truth_label, out);
  return out;
}

// A box on a flat seabed, in the height profile and as a closed section: every sample of its
// analytic shadow [r_top, r_end] is shadow cast by it, every shadow sample is its, and the
// shadow's ground length is h y_b / (H - h).
TEST(ShadowAttribution, BoxOnFlatSeabedCastsItsWholeShadow) {
  const double H = 10.0, h = 1.5, y_f = 20.0, y_b = 22.0, dr = 0.02;
  const Samples s{dr};
  const double r_top = std::hypot(y_b, H - h);  // the far top edge
  const double r_end = r_top * H / (H - h);     // where its ray lands
  const double length_m = h * y_b / (H - h);    // 3.882 m
  for (const bool section : {false, true}) {
    SCOPED_TRACE(section ? "closed section" : "height profile");
    BeamProfile prof = section ? flat_profile(H, 38.0) : profile_box(H, h, y_f, y_b, 38.0, 3);
    if (section) add_box_section(prof, h, y_f, y_b, 3);
    SideEcho e;
    render_side(prof, params(dr, 2000), e);
    for (std::size_t i = s.first_inside(r_top) + 1; i <= s.last_inside(r_end) - 1; ++i) {
      ASSERT_EQ(e.truth_class[i], SampleClass::shadow) << i;
      ASSERT_EQ(e.truth_label[i], 3) << i;
    }
    const std::vector<std::uint32_t> inst = instances(e);
    std::size_t last = 0, count = 0;
    for (std::size_t i = 0; i < e.truth_class.size(); ++i) {
      if (e.truth_class[i] != SampleClass::shadow) continue;
      EXPECT_EQ(e.truth_label[i], 3) << i;
      EXPECT_EQ(inst[i], 3u) << i;
      EXPECT_GE(static_cast<double>(i + 1) * dr, std::hypot(y_f, H)) << i;
      last = i;
      ++count;
    }
    EXPECT_GT(count, static_cast<std::size_t>((r_end - r_top) / dr) - 2);
    // Across track: the far end of the last shadow sample, on the ground, is y_b + length_m to
    // within one sample's ground extent there (dr r / y).
    const double r_last = static_cast<double>(last + 1) * dr;
    const double ground_m = std::sqrt(r_last * r_last - H * H) - y_b;
    const double y_e = y_b + length_m;
    EXPECT_NEAR(ground_m, length_m, dr * std::hypot(y_e, H) / y_e);
  }
}

// A moored sphere: its shadow on the seabed lies between the landing ranges of its two tangent
// rays, detached from its echo by lit seabed, and every sample of it is the sphere's.
TEST(ShadowAttribution, MooredTargetsDetachedShadowIsItsOwn) {
  const double H = 10.0, yc = 12.0, zc = 4.0, a = 0.5, dr = 0.02;
  const Samples s{dr};
  BeamProfile prof = flat_profile(H, 38.0);
  std::vector<double> ys, zs;
  const int n = 720;
  for (int k = 0; k < n; ++k) {  // clockwise in (y, z)
    const double phi = -2.0 * std::numbers::pi * k / n;
    ys.push_back(yc + a * std::cos(phi));
    zs.push_back(zc + a * std::sin(phi));
  }
  prof.add_section(ys.data(), zs.data(), ys.size(), 9, 0);
  SideEcho e;
  render_side(prof, params(dr, 2000), e);
  const double theta_c = std::atan2(H - zc, yc);
  const double alpha = std::asin(a / std::hypot(yc, H - zc));
  const double r0 = H / std::sin(theta_c + alpha), r1 = H / std::sin(theta_c - alpha);
  for (std::size_t i = s.first_inside(r0) + 1; i <= s.last_inside(r1) - 1; ++i) {
    ASSERT_EQ(e.truth_class[i], SampleClass::shadow) << i;
    ASSERT_EQ(e.truth_label[i], 9) << i;
  }
  const std::vector<std::uint32_t> inst = instances(e);
  std::size_t first = e.truth_class.size(), last = 0;
  for (std::size_t i = 0; i < e.truth_class.size(); ++i) {
    if (e.truth_class[i] != SampleClass::shadow) continue;
    EXPECT_EQ(inst[i], 9u) << i;
    first = std::min(first, i);
    last = i;
  }
  EXPECT_NEAR(static_cast<double>(first) * dr, r0, dr);
  EXPECT_NEAR(static_cast<double>(last + 1) * dr, r1, dr);
  // Detached: lit seabed between the sphere's echo and its shadow.
  EXPECT_EQ(e.truth_class[first - 1], SampleClass::seabed);
  EXPECT_EQ(e.truth_class[s.first_inside(0.5 * (std::hypot(yc, H - zc) + r0))],
            SampleClass::seabed);
}

// A ridge with no object: its shadow is cast by relief, label and instance 0.
TEST(ShadowAttribution, ReliefShadowHasNoInstance) {
  const double H = 10.0, dr = 0.02;
  BeamProfile p;
  p.sensor_z_m = H;
  p.add_node(0.0, 0.0);
  add_flat(p, 0.0, 15.0, 0.1);
  p.add_node(18.0, 1.0);  // the crest, its back slope steeper than the ray
  p.add_node(18.2, 0.0);
  add_flat(p, 18.2, 38.0, 0.1);
  SideEcho e;
  render_side(p, params(dr, 2000), e);
  const double r_crest = std::hypot(18.0, H - 1.0);
  const double r_end = r_crest * H / (H - 1.0);  // the crest's ray lands at y = 20
  const Samples s{dr};
  for (std::size_t i = s.first_inside(r_crest) + 1; i <= s.last_inside(r_end) - 1; ++i) {
    ASSERT_EQ(e.truth_class[i], SampleClass::shadow) << i;
  }
  const std::vector<std::uint32_t> inst = instances(e);
  for (std::size_t i = 0; i < e.truth_class.size(); ++i) {
    if (e.truth_class[i] != SampleClass::shadow) continue;
    EXPECT_EQ(e.truth_label[i], 0) << i;
    EXPECT_EQ(inst[i], 0u) << i;
  }
}

// A box with a higher ridge behind it: the seabed behind the ridge whose ray passes through the
// box is the box's (an object wins over relief) up to where the box's own shadow ends
// (y_b H / (H - h)); beyond, the ridge alone hides it (0). The same for the box in the height
// profile and as a closed section.
TEST(ShadowAttribution, ObjectWinsOverReliefUpToItsOwnShadowEnd) {
  const double H = 10.0, h = 1.0, y_f = 18.0, y_b = 20.0, dr = 0.02;
  const double crest_y = 21.0, crest_z = 2.0, back_y = 21.1;
  for (const bool section : {false, true}) {
    SCOPED_TRACE(section ? "closed section" : "height profile");
    BeamProfile p;
    p.sensor_z_m = H;
    p.add_node(0.0, 0.0);
    add_flat(p, 0.0, y_f - 0.1, 0.1);
    p.add_node(y_f, 0.0);
    if (!section) {
      p.add_node(y_f, h, 7);
      p.add_node(y_b, h, 7);
      p.add_node(y_b, 0.0, 7);
    } else {
      p.add_node(y_b, 0.0);
      add_box_section(p, h, y_f, y_b, 7);
    }
    p.add_node(20.5, 0.0);
    p.add_node(crest_y, crest_z);
    p.add_node(back_y, 0.0);
    add_flat(p, back_y, 38.0, 0.1);
    SideEcho e;
    render_side(p, params(dr, 2000), e);
    const Samples s{dr};
    const double r_back = std::hypot(back_y, H);                // foot of the ridge's back
    const double r_box_end = std::hypot(y_b * H / (H - h), H);  // y = 22.22
    const double r_ridge_end = std::hypot(crest_y * H / (H - crest_z), H);  // y = 26.25
    for (std::size_t i = s.first_inside(r_back) + 1; i <= s.last_inside(r_box_end) - 1; ++i) {
      ASSERT_EQ(e.truth_class[i], SampleClass::shadow) << i;
      ASSERT_EQ(e.truth_label[i], 7) << i;
    }
    for (std::size_t i = s.first_inside(r_box_end) + 1; i <= s.last_inside(r_ridge_end) - 1; ++i) {
      ASSERT_EQ(e.truth_class[i], SampleClass::shadow) << i;
      ASSERT_EQ(e.truth_label[i], 0) << i;
    }
  }
}

// Without a recorded caster (truth from elsewhere, id < 0) the run rule still applies; a recorded
// one is taken as it is, across seabed and water column between the caster and its shadow.
TEST(ShadowAttribution, SideInstancesTakeTheRecordedCaster) {
  using C = SampleClass;
  const std::vector<C> cls = {C::object, C::water_column, C::seabed, C::shadow, C::shadow,
                              C::seabed, C::shadow,       C::object, C::shadow, C::shadow};
  const std::vector<std::int32_t> id = {4, -1, 0, 4, 4, 0, 0, 6, -1, -1};
  std::vector<std::uint32_t> out;
  labels::side_instances(cls, id, out);
  EXPECT_EQ(out, (std::vector<std::uint32_t>{4, 0, 0, 4, 4, 0, 0, 6, 6, 6}));
}

// A scene on a flat seabed: a box along the track, a rock, a moored sphere, a free-spanning pipe
// and a turned box (the steel smooth, so that the box's top is the analytic one). No shadow pixel
// of the waterfall or the mosaic is left without its object, and the box's shadow spans the pings
// that cross the box (its length along track) and, in each, the slant ranges of its analytic shadow
// across track.
const std::string kScene = test::flat_scene("shadow-attribution", 3, 120, 120, 15, 2.0, 6) + R"(
    - {name: a, waypoints: [{east_m: -30, north_m: 0}, {east_m: 30, north_m: 0}]}
objects:
  - {type: box, id: 3, position: {east_m: -12, north_m: 14}, size_m: [4, 2, 1.5], heading_deg: 90,
     material: steel}
  - {type: rock, id: 5, position: {east_m: 4, north_m: 10}, size_m: [2, 1.6, 1.0]}
  - {type: moored, id: 9, position: {east_m: 16, north_m: 8}, shape: sphere, diameter_m: 1.0,
     height_m: 3}
  - {type: pipe, id: 8, position: {east_m: 5, north_m: -12}, heading_deg: 90, length_m: 12,
     diameter_m: 0.5, clearance_m: 0.8}
  - {type: box, id: 4, position: {east_m: -8, north_m: -18}, size_m: [2, 2, 1.0], heading_deg: 20}
materials:
  - {name: steel, roughness_rms_m: 0}  # smooth: the box's top edge is straight
sonar: {frequency_khz: 600, range_m: 30, samples: 600}
output:
  labels: {coco: true}
)";

using Raster = test::LabelRaster;
Raster read(const fs::path& path) {
  return test::read_label_raster(path);
}

TEST(ShadowAttribution, SceneShadowsAllHaveTheirObjectAndTheBoxsExtent) {
  const fs::path dir =
      fs::temp_directory_path() / ("sonarsynth_shadow_attribution_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scene = dir / "scene.yaml";
  std::ofstream(scene) << kScene;
  run_simulation(scene.string(), dir / "out", RunOptions{});
  const SimulationSetup setup = load_simulation(scene.string());

  // Every shadow pixel has its object; every object has shadow pixels.
  for (const auto& [cls_name, inst_name] :
       {std::pair<std::string, std::string>{"a_truth_class.tif", "a_truth_instance.tif"},
        {"truth_mosaic_class.tif", "truth_mosaic_instance.tif"}}) {
    SCOPED_TRACE(cls_name);
    const Raster cls = read(dir / "out" / cls_name);
    const Raster inst = read(dir / "out" / inst_name);
    ASSERT_EQ(cls.values.size(), inst.values.size());
    std::map<std::uint32_t, std::size_t> shadow;
    for (std::size_t i = 0; i < cls.values.size(); ++i) {
      if (cls.values[i] == 3) ++shadow[inst.values[i]];
    }
    EXPECT_EQ(shadow.count(0), 0u) << shadow[0] << " shadow pixels without an object";
    for (std::uint32_t id : {3u, 4u, 5u, 8u, 9u}) EXPECT_GT(shadow[id], 0u) << id;
  }

  // The box along the track (id 3, port side): its shadow per ping.
  const Raster cls = read(dir / "out" / "a_truth_class.tif");
  const Raster inst = read(dir / "out" / "a_truth_instance.tif");
  const Survey survey = setup.make_survey();
  ASSERT_EQ(cls.rows, survey.pings_in_line(0));
  const std::size_t side = cls.cols / 2;
  const double dr = setup.config.sonar.sample_spacing_m();
  const double w = setup.config.sonar.pulse_window_m();
  const ObjectPrimitive* box = nullptr;
  for (const ObjectPrimitive& o : setup.scene.objects.primitives()) {
    if (o.id == 3) box = &o;
  }
  ASSERT_NE(box, nullptr);
  // Its along-track ends and far top edge (heading east: u along x, v across).
  const double x0 = box->centre_xy_m.x() - box->half_extent_m.x();
  const double x1 = box->centre_xy_m.x() + box->half_extent_m.x();
  const double y_b = box->centre_xy_m.y() + box->half_extent_m.y();
  const double top_z = box->base_at(0.0) + 2.0 * box->half_extent_m.z();
  double step_m = 0.0;
  std::size_t rows_with_shadow = 0;
  for (std::size_t row = 0; row < cls.rows; ++row) {
    const PingPose pose = survey.pose(row, setup.scene.bathymetry);
    step_m = pose.speed_m_s * survey.ping_period_s();
    const double x = pose.sensor_xy_m.x();
    const double H = pose.altitude_m;                              // flat seabed
    const double h = top_z - (pose.sensor_z_m - pose.altitude_m);  // the box's height
    const double r_top = std::hypot(y_b - pose.sensor_xy_m.y(), H - h);
    const double r_end = r_top * H / (H - h);
    bool any = false;
    for (std::size_t k = 0; k < side; ++k) {
      const std::size_t i = row * cls.cols + side - 1 - k;  // port: FAR -> NEAR
      const double r0 = static_cast<double>(k + 1) * dr - std::max(w, dr);
      const double r1 = static_cast<double>(k + 1) * dr;
      const bool box_shadow = cls.values[i] == 3 && inst.values[i] == 3;
      any = any || box_shadow;
      if (x > x0 + step_m && x < x1 - step_m && r0 > r_top + dr && r1 < r_end - dr) {
        ASSERT_TRUE(box_shadow) << "row " << row << " sample " << k;
      }
      if (box_shadow) {
        ASSERT_GT(r1, r_top - dr) << "row " << row << " sample " << k;
        ASSERT_LT(r0, r_end + dr) << "row " << row << " sample " << k;
      }
    }
    if (x < x0 - step_m || x > x1 + step_m) {
      EXPECT_FALSE(any) << "row " << row;
    }
    rows_with_shadow += any;
  }
  // Along track: the box's 4 m, to a ping at either end.
  EXPECT_NEAR(static_cast<double>(rows_with_shadow) * step_m, x1 - x0, 2.0 * step_m);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth
