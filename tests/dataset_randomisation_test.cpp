// SPDX-License-Identifier: MIT
// Domain randomisation in dataset specs (docs/dataset.md, "Domain randomisation"): the knobs
// leave the draws of a spec that does not use them unchanged, every drawn value is the value
// the scene file holds (read back by the scene loader and a YAML parser), and a spec whose
// ranges the scene file would refuse is refused when it is loaded, naming the file, the key and
// the value.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>

#include "cli_test_util.hpp"
#include "dataset_test_spec.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/dataset.hpp"
#include "sonarsynth/formats/config/option_table.hpp"
#include "sonarsynth/formats/config/run_check.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"
#include "sonarsynth/sonar_presets.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// The tests' tiny spec (a 6 m line, 10 m range) with ranges where it has fixed values and a
// choice of noise models.
std::string base_spec() {
  std::string t = test::tiny_spec(60);
  t = replaced(t, "name: tiny\nseed: 99", "name: knobs\nseed: 5");
  t = replaced(t, "material: {sand: 2, mud: 1}", "material: {sand: 2, mud: 1, gravel: 1}");
  t = replaced(t, "speed_m_s: 3", "speed_m_s: [2, 3]");
  t = replaced(t, "range_m: 10,", "range_m: [9, 10],");
  return replaced(t, "model: speckle,", "model: {speckle: 3, none: 1},");
}

// The base spec with every knob randomised, and meshes (the shipped mine and a copy of the
// wreck named by a path relative to the spec file).
std::string every_knob_spec() {
  std::string t = base_spec();
  t = replaced(t, "  slope_deg: [0, 2]\n",
               "  slope_deg: [0, 2]\n  texture_shape: [2, 30]\n  reflectivity: [0.3, 0.7]\n");
  t = replaced(t, "wavelength_m: [5, 10]}", "wavelength_m: [5, 10], persistence: [0.4, 0.6]}");
  t = replaced(t, "amplitude_m: [0.02, 0.04]}",
               "amplitude_m: [0.02, 0.04], bandwidth: [0.05, 0.3], amplitude_variation: [0, 1], "
               "asymmetry: [0, 0.5]}");
  t = replaced(t, "    moored: {diameter_m: [0.4, 0.8], height_m: [2, 3]}\n",
               "    moored: {diameter_m: [0.4, 0.8], height_m: [2, 3]}\n"
               "    mesh: {weight: 3, models: {mine: 2, ../models/wreck.obj: 1}, "
               "scale: [0.1, 0.3]}\n");
  t = replaced(t, "  speed_m_s: [2, 3]\n",
               "  speed_m_s: [2, 3]\n"
               "  altitude_time_constant_s: [0, 2]\n"
               "  disturbance: {roll_deg: [0, 3], pitch_deg: [0, 2], yaw_deg: [0, 2], "
               "heave_m: [0, 0.1], period_s: [4, 9], altitude_m: [0, 0.2], "
               "heading_wander_deg: [0, 3], wander_period_s: [60, 200]}\n");
  t = replaced(t, "samples: 200}", "samples: 200, frequency_khz: [550, 650]}");
  t += "output: {seabed_median_dbfs: [-14, -4]}\n";
  return t;
}

// The spec as a file in the samples' datasets directory's place: `../models/wreck.obj` is then
// the shipped wreck.
DatasetSpec every_knob(int count = 60) {
  const std::string file = std::string(SONARSYNTH_SAMPLES_DIR) + "/datasets/knobs.yaml";
  return load_dataset_spec_from_string(
      replaced(every_knob_spec(), "count: 60", "count: " + std::to_string(count)), file);
}

DatasetSpec from(const std::string& text) {
  return load_dataset_spec_from_string(text, "spec.yaml");
}

TEST(DatasetRandomisation, UnusedKeysLeaveTheSceneTextUnchanged) {
  const DatasetSpec base = from(base_spec());
  // Empty knob sections; ripple knobs of a spec that never draws ripples.
  const DatasetSpec empty_sections = from(
      replaced(base_spec(), "  speed_m_s: [2, 3]\n", "  speed_m_s: [2, 3]\n  disturbance: {}\n") +
      "output: {}\n");
  const std::string no_ripples =
      replaced(base_spec(), "ripples: {probability: 0.5,", "ripples: {probability: 0,");
  const DatasetSpec unused_ripple_knobs =
      from(replaced(no_ripples, "ripples: {probability: 0,",
                    "ripples: {probability: 0, bandwidth: 0.3, asymmetry: [0, 0.5],"));
  const DatasetSpec without = from(no_ripples);
  for (std::size_t i = 0; i < 20; ++i) {
    EXPECT_EQ(dataset_item_scene(empty_sections, i).yaml, dataset_item_scene(base, i).yaml) << i;
    EXPECT_EQ(dataset_item_scene(unused_ripple_knobs, i).yaml, dataset_item_scene(without, i).yaml)
        << i;
  }
}

TEST(DatasetRandomisation, NewKnobsLeaveTheOtherDrawsAsTheyWere) {
  // Every knob added, meshes as a fifth object type: each value the base spec draws is drawn
  // the same (the knobs take fields of their own), except the object types (the weights
  // changed) and what hangs on the type.
  const DatasetSpec base = from(base_spec()), knobs = every_knob();
  std::size_t compared = 0;
  for (std::size_t i = 0; i < 20; ++i) {
    const DatasetItemScene a = dataset_item_scene(base, i), b = dataset_item_scene(knobs, i);
    for (const auto& [key, v] : a.drawn_numbers) {
      if (key.starts_with("objects[")) continue;
      ASSERT_EQ(b.drawn_numbers.count(key), 1u) << key;
      EXPECT_EQ(b.drawn_numbers.at(key), v) << key;
      ++compared;
    }
    for (const auto& [key, v] : a.drawn_names) {
      if (key.starts_with("objects[")) continue;
      EXPECT_EQ(b.drawn_names.at(key), v) << key;
    }
    // The objects' positions and headings do not depend on their type.
    for (const auto& [key, v] : a.drawn_numbers) {
      if (key.ends_with("along_track_m") || key.ends_with("across_track_m") ||
          key.ends_with("heading_deg")) {
        EXPECT_EQ(b.drawn_numbers.at(key), v) << key;
      }
    }
  }
  EXPECT_GT(compared, 200u);
}

// One component of the drawn bathymetry generator by type (an undefined node if none).
YAML::Node component(const YAML::Node& generate, const std::string& type) {
  for (const YAML::Node& c : generate["components"]) {
    if (c["type"].as<std::string>() == type) return c;
  }
  return YAML::Node(YAML::NodeType::Undefined);
}

// Every value recorded for an item is the value its scene file holds, read back by the scene
// loader (the simulation keys, materials, objects) or a YAML parser (the generator's keys, which
// the loaded scene keeps only as heights).
void expect_drawn_values_in_scene(const DatasetItemScene& item) {
  SCOPED_TRACE(item.yaml);
  SimulationOverrides one_thread;
  one_thread.threads = 1;
  const SimulationSetup setup =
      load_simulation_from_string(item.yaml, "item.yaml", ".", one_thread);
  const YAML::Node doc = YAML::Load(item.yaml);
  const YAML::Node generate = doc["bathymetry"]["generate"];
  std::set<std::string> checked;
  const auto same = [&](const std::string& key, double scene_value, double tolerance = 1e-9) {
    checked.insert(key);
    ASSERT_EQ(item.drawn_numbers.count(key), 1u) << key;
    EXPECT_NEAR(item.drawn_numbers.at(key), scene_value, tolerance) << key;
  };
  const auto same_name = [&](const std::string& key, const std::string& scene_value) {
    checked.insert(key);
    ASSERT_EQ(item.drawn_names.count(key), 1u) << key;
    EXPECT_EQ(item.drawn_names.at(key), scene_value) << key;
  };
  // The simulation keys, through the option table's accessors of the loaded setup.
  for (const auto& [key, v] : item.drawn_numbers) {
    if (key.starts_with("survey.") || key.starts_with("sonar.") || key.starts_with("noise.") ||
        key.starts_with("output.")) {
      if (key == "survey.heading_deg") continue;
      same(key, options::at(key).get(setup), 1e-9 * std::max(1.0, std::abs(v)));
    }
  }
  const auto& noise = options::at("noise.model");
  same_name("noise.model",
            std::string(noise.choices.at(static_cast<std::size_t>(noise.get(setup)))));
  same_name("sonar.preset", doc["sonar"]["preset"].as<std::string>());
  EXPECT_EQ(setup.config.sonar.tilt_rad,
            sonar_preset(item.drawn_names.at("sonar.preset")).tilt_rad);
  // The line's azimuth from its waypoints (written to 1 mm: 3 m from the centre, 0.02 deg).
  const Eigen::Vector2d d =
      setup.lines.at(0).waypoints_xy_m.back() - setup.lines.at(0).waypoints_xy_m.front();
  const double heading_deg = std::atan2(d.x(), d.y()) * 180.0 / std::numbers::pi;
  same("survey.heading_deg",
       std::remainder(heading_deg - item.drawn_numbers.at("survey.heading_deg"), 360.0) +
           item.drawn_numbers.at("survey.heading_deg"),
       0.03);

  // The seabed: material and its overrides from the loaded scene, the generator from the text.
  const Scene& scene = setup.scene;
  const Material& m = scene.materials[scene.material_map.default_material()];
  same_name("seabed.material", m.name);
  if (item.drawn_numbers.count("seabed.texture_shape")) {
    same("seabed.texture_shape", m.texture_shape_nu);
  }
  if (item.drawn_numbers.count("seabed.reflectivity")) {
    same("seabed.reflectivity", m.paper_reflectivity);
  }
  same("seabed.depth_m", generate["depth_m"].as<double>());
  same("seabed.slope_deg", component(generate, "plane")["slope_deg"].as<double>());
  same("seabed.downslope_azimuth_deg",
       component(generate, "plane")["downslope_azimuth_deg"].as<double>());
  for (const std::string type : {"fbm", "ripples"}) {
    const std::string prefix = type == "fbm" ? "seabed.roughness." : "seabed.ripples.";
    const YAML::Node c = component(generate, type);
    if (type == "ripples") same("seabed.ripples", c.IsDefined() ? 1.0 : 0.0);
    if (!c.IsDefined()) continue;
    for (const auto& kv : c) {
      const std::string k = kv.first.as<std::string>();
      if (k == "type" || k == "octaves") continue;
      same(prefix + k, kv.second.as<double>());
    }
  }

  // The objects: their count and types from the loaded scene, their keys from the text, their
  // place on the line (written to 1 mm from the unrounded draws) from the positions.
  std::set<std::int32_t> ids;
  for (const ObjectPrimitive& p : scene.objects.primitives()) ids.insert(p.id);
  same("objects.count", static_cast<double>(ids.size()));
  const YAML::Node& wps = doc["survey"]["lines"][0]["waypoints"];
  const Eigen::Vector2d a(wps[0]["east_m"].as<double>(), wps[0]["north_m"].as<double>());
  const Eigen::Vector2d b(wps[1]["east_m"].as<double>(), wps[1]["north_m"].as<double>());
  const Eigen::Vector2d fwd = (b - a).normalized(), stbd(fwd.y(), -fwd.x());
  const Eigen::Vector2d mid = 0.5 * (a + b);
  const std::map<std::string, std::string> object_keys = {
      {"heading_deg", "heading_deg"}, {"burial", "embed"},      {"diameter_m", "diameter_m"},
      {"length_m", "length_m"},       {"height_m", "height_m"}, {"scale", "scale"}};
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const std::string o = "objects[" + std::to_string(k) + "].";
    const YAML::Node n = doc["objects"][k];
    const std::string type = n["type"].as<std::string>();
    same_name(o + "type", type);
    const Eigen::Vector2d p(n["position"]["east_m"].as<double>(),
                            n["position"]["north_m"].as<double>());
    same(o + "along_track_m", (p - mid).dot(fwd), 2e-3);
    same(o + "across_track_m", (p - mid).dot(stbd), 2e-3);
    for (const auto& [spec_key, scene_key] : object_keys) {
      if (n[scene_key].IsDefined()) same(o + spec_key, n[scene_key].as<double>());
    }
    if (type == "box") {
      same(o + "length_m", n["size_m"][0].as<double>());
      same(o + "width_m", n["size_m"][1].as<double>());
      same(o + "height_m", n["size_m"][2].as<double>());
    }
    if (type == "mesh") {
      const std::string model = item.drawn_names.at(o + "model");
      const fs::path expected = fs::path(SONARSYNTH_SAMPLES_DIR) / "models" /
                                (model == "mine" ? "mine.obj" : "wreck.obj");
      same_name(o + "model", model);
      EXPECT_TRUE(fs::equivalent(n["file"].as<std::string>(), expected)) << n["file"];
      EXPECT_TRUE(fs::path(n["file"].as<std::string>()).is_absolute());
    }
  }
  // Nothing recorded went unchecked.
  for (const auto& [key, v] : item.drawn_numbers) EXPECT_EQ(checked.count(key), 1u) << key;
  for (const auto& [key, v] : item.drawn_names) EXPECT_EQ(checked.count(key), 1u) << key;
}

TEST(DatasetRandomisation, DrawnValuesAreTheValuesOfTheScene) {
  const DatasetSpec s = every_knob(30);
  std::set<std::string> types;
  for (std::size_t i = 0; i < s.count; ++i) {
    const DatasetItemScene item = dataset_item_scene(s, i);
    for (const auto& [k, n] : item.object_counts) types.insert(k);
    expect_drawn_values_in_scene(item);
    if (HasFatalFailure() || HasNonfatalFailure()) break;
  }
  EXPECT_EQ(types, (std::set<std::string>{"box", "mesh", "moored", "pipe", "rock"}));
  // The base spec (no knob) as well.
  for (std::size_t i = 0; i < 5; ++i)
    expect_drawn_values_in_scene(dataset_item_scene(from(base_spec()), i));
}

class DatasetRandomisationRun : public test::ScratchDirTest {};

TEST_F(DatasetRandomisationRun, EveryItemOfAValidSpecPassesTheSceneChecks) {
  // 50 items of the spec with every knob randomised: each scene loads and passes the checks
  // `simulate` makes before rendering (coverage, the sensor in the water and above the seabed,
  // range longer than the altitude, pings, output and memory within the limits).
  const DatasetSpec s = every_knob(50);
  for (std::size_t i = 0; i < s.count; ++i) {
    const DatasetItemScene item = dataset_item_scene(s, i);
    SimulationOverrides o;
    o.threads = 1;
    o.quality = s.quality;
    try {
      const SimulationSetup setup = load_simulation_from_string(item.yaml, "item.yaml", ".", o);
      check_simulation("item.yaml", setup, ProductPlan{false, true, true, 0.25}, dir_ / "out");
    } catch (const std::exception& e) {
      ADD_FAILURE() << "item " << i << ": " << e.what() << "\n" << item.yaml;
    }
  }
}

TEST_F(DatasetRandomisationRun, ModelPathsAreRelativeToTheSpecAndAbsoluteInTheScene) {
  // A spec in its own directory naming a model beside it: the drawn scene names the model's
  // absolute path, so the scene loads from the item's directory, wherever that is.
  fs::create_directories(dir_ / "specs" / "models");
  fs::copy_file(fs::path(SONARSYNTH_SAMPLES_DIR) / "models" / "mine.obj",
                dir_ / "specs" / "models" / "mine.obj");
  const std::string text =
      replaced(base_spec(), "    moored: {diameter_m: [0.4, 0.8], height_m: [2, 3]}\n",
               "    mesh: {weight: 100, models: models/mine.obj}\n");
  const fs::path spec = write("specs/spec.yaml", text);
  const DatasetSpec s = load_dataset_spec(spec.string());
  const DatasetItemScene item = dataset_item_scene(s, 0);
  ASSERT_EQ(item.object_counts.count("mesh"), 1u) << item.yaml;
  const fs::path item_dir = dir_ / "items" / "000000";
  fs::create_directories(item_dir);
  std::ofstream(item_dir / "scene.yaml") << item.yaml;
  const SimulationSetup setup = load_simulation((item_dir / "scene.yaml").string());
  EXPECT_EQ(setup.scene.objects.primitives().size(),
            static_cast<std::size_t>(item.drawn_numbers.at("objects.count")));
  const YAML::Node doc = YAML::Load(item.yaml);
  for (const YAML::Node& o : doc["objects"]) {
    if (o["type"].as<std::string>() != "mesh") continue;
    EXPECT_TRUE(fs::path(o["file"].as<std::string>()).is_absolute()) << o["file"];
    EXPECT_TRUE(
        fs::equivalent(o["file"].as<std::string>(), dir_ / "specs" / "models" / "mine.obj"));
  }
  // The model gone, the spec is refused on loading, naming the file, the key and the model.
  fs::remove(dir_ / "specs" / "models" / "mine.obj");
  try {
    load_dataset_spec(spec.string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(spec.string() + ": objects.types.mesh.models: 'models/mine.obj'", 0), 0u)
        << msg;
  }
}

TEST(DatasetRandomisation, TheSampleSpecDrawsEveryKnob) {
  const DatasetSpec s =
      load_dataset_spec(std::string(SONARSYNTH_SAMPLES_DIR) + "/datasets/randomised.yaml");
  std::set<std::string> keys;
  for (std::size_t i = 0; i < 20; ++i) {
    const DatasetItemScene item = dataset_item_scene(s, i);
    for (const auto& [k, v] : item.drawn_numbers) keys.insert(k.substr(0, k.find('[')));
  }
  for (const std::string k :
       {"sonar.frequency_khz", "survey.disturbance.roll_deg", "survey.disturbance.altitude_m",
        "survey.altitude_time_constant_s", "output.seabed_median_dbfs", "seabed.texture_shape",
        "seabed.ripples.bandwidth", "seabed.ripples.amplitude_variation",
        "seabed.roughness.persistence"}) {
    EXPECT_EQ(keys.count(k), 1u) << k;
  }
  EXPECT_GT(s.knobs.size(), 15u);
}

// A spec the scene file would refuse: each case replaces one piece of the valid spec and names
// the key, the value and the constraint in its error.
struct Rejected {
  std::string name, from, to;
  std::vector<std::string> expected;
};

// Names the case in test listings (ctest), instead of its bytes.
void PrintTo(const Rejected& r, std::ostream* os) {
  *os << r.name;
}

class DatasetRejected : public ::testing::TestWithParam<Rejected> {};

TEST_P(DatasetRejected, NamesTheFileTheKeyAndTheValue) {
  const Rejected& c = GetParam();
  ASSERT_NO_THROW(every_knob());
  const std::string file = std::string(SONARSYNTH_SAMPLES_DIR) + "/datasets/bad.yaml";
  try {
    load_dataset_spec_from_string(replaced(every_knob_spec(), c.from, c.to), file);
    FAIL() << "no error for " << c.to;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(file + ": ", 0), 0u) << msg;
    for (const std::string& x : c.expected) {
      EXPECT_NE(msg.find(x), std::string::npos) << msg << " (wanted " << x << ")";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, DatasetRejected,
    ::testing::Values(
        // A speed that rounds to 0 in the scene file (1 mm/s).
        Rejected{"SpeedBelowTheScenesBound",
                 "speed_m_s: [2, 3]",
                 "speed_m_s: [1e-9, 0.0004]",
                 {"survey.speed_m_s = [1e-9, 0.0004]", "speed_m_s > 0"}},
        // A line that needs more pings than the scene's limits.max_pings.
        Rejected{"SpeedTooLowForThePingLimit",
                 "line_length_m: 6\n  altitude_m: [3, 5]\n  speed_m_s: [2, 3]",
                 "line_length_m: 100\n  altitude_m: [3, 5]\n  speed_m_s: [0.001, 3]",
                 {"survey.speed_m_s = '[0.001, 3]'", "limits.max_pings = 2000000"}},
        Rejected{"RangeBelowTheScenesBound",
                 "range_m: [9, 10]",
                 "range_m: 1e-6",
                 {"sonar.range_m = '1e-6'", "range_m > 0"}},
        Rejected{"RangeNotLongerThanTheAltitude",
                 "range_m: [9, 10]",
                 "range_m: [5, 10]",
                 {"sonar.range_m = '[5, 10]'", "the shortest range (5 m) > the highest altitude"}},
        Rejected{"AltitudeBelowTheScenesBound",
                 "altitude_m: [3, 5]",
                 "altitude_m: [0.0001, 5]",
                 {"survey.altitude_m = [0.0001, 5]", "altitude_m > 0"}},
        Rejected{"AltitudeWanderReachesTheSeabed",
                 "altitude_m: [0, 0.2]",
                 "altitude_m: [0, 1.5]",
                 {"survey.altitude_m = '[3, 5]'", "the sensor's motion"}},
        Rejected{"DepthLessReliefAboveTheSensor",
                 "depth_m: [10, 14]",
                 "depth_m: [6, 14]",
                 {"seabed.depth_m = '6'", "relief", "survey.altitude_m"}},
        Rejected{"DepthBeyondTheGenerator",
                 "depth_m: [10, 14]",
                 "depth_m: [10, 11500]",
                 {"seabed.depth_m = '[10, 11500]'", "depth_m <= 11000"}},
        Rejected{"GridTooLarge",
                 "line_length_m: 6",
                 "line_length_m: 100000",
                 {"seabed.cell_m = '0.5'", "cells <="}},
        Rejected{"RipplesFinerThanTwoCells",
                 "wavelength_m: [1, 2], amplitude_m",
                 "wavelength_m: [0.6, 2], amplitude_m",
                 {"seabed.ripples.wavelength_m = '[0.6, 2]'", "2 cells"}},
        Rejected{"RippleBandwidth",
                 "bandwidth: [0.05, 0.3]",
                 "bandwidth: [0.05, 0.7]",
                 {"seabed.ripples.bandwidth = [0.05, 0.7]", "bandwidth >= 0 and <= 0.5"}},
        Rejected{"RippleAsymmetryRoundsToOne",
                 "asymmetry: [0, 0.5]",
                 "asymmetry: [0, 0.9996]",
                 {"seabed.ripples.asymmetry", "asymmetry >= 0 and < 1"}},
        Rejected{"Roll",
                 "roll_deg: [0, 3]",
                 "roll_deg: [0, 95]",
                 {"survey.disturbance.roll_deg = [0, 95]", "roll_deg >= 0 and <= 89"}},
        Rejected{"Frequency",
                 "frequency_khz: [550, 650]",
                 "frequency_khz: [0, 650]",
                 {"sonar.frequency_khz = [0, 650]", "frequency_khz > 0"}},
        Rejected{"TextureShape",
                 "texture_shape: [2, 30]",
                 "texture_shape: [-1, 30]",
                 {"seabed.texture_shape = [-1, 30]", "texture_shape >= 0"}},
        Rejected{"GainAndItsTarget",
                 "output: {seabed_median_dbfs: [-14, -4]}",
                 "output: {seabed_median_dbfs: [-14, -4], gain_db: 3}",
                 {"output.gain_db", "not both"}},
        Rejected{"Gain",
                 "output: {seabed_median_dbfs: [-14, -4]}",
                 "output: {gain_db: [0, 200]}",
                 {"output.gain_db = [0, 200]", "gain_db >= -150 and <= 150"}},
        Rejected{"SamplesBeyondXtfReaders",
                 "samples: 200",
                 "samples: 9000",
                 {"sonar.samples = '9000'", "<= 8192"}},
        Rejected{"UnknownKnob",
                 "heave_m: [0, 0.1]",
                 "surge_m: [0, 0.1]",
                 {"survey.disturbance", "surge_m"}},
        Rejected{"MissingModel",
                 "../models/wreck.obj: 1",
                 "../models/nothere.obj: 1",
                 {"objects.types.mesh.models", "'../models/nothere.obj'", "nothere.obj is none"}},
        Rejected{"MeshScale",
                 "scale: [0.1, 0.3]",
                 "scale: [0.0001, 0.3]",
                 {"objects.types.mesh.scale", "scale > 0"}}),
    [](const ::testing::TestParamInfo<Rejected>& p) { return p.param.name; });

}  // namespace
}  // namespace sonarsynth
