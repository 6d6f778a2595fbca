// SPDX-License-Identifier: MIT
// load_scene_from_string / load_simulation_from_string: the same scene and simulation as from
// the file, relative paths against the given directory, errors naming the given name.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/scene_file.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The real_ledges sample reads a BAG by a relative path: from the text with the samples
// directory as base, the scene equals the one loaded from the file.
// Expects `load()` (which loads `yaml`) to throw an InputError whose message holds `part`.
template <class Load>
void expect_input_error_from(Load load, const std::string& yaml, const std::string& part) {
  try {
    load();
    ADD_FAILURE() << "no error for:\n" << yaml;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(SceneFromString, EqualsTheSceneFromTheFile) {
  const fs::path file = fs::path(SONARSYNTH_SAMPLES_DIR) / "real_ledges.yaml";
  const SimulationSetup a = load_simulation(file.string());
  const SimulationSetup b =
      load_simulation_from_string(slurp(file), "real_ledges.yaml", file.parent_path());
  EXPECT_EQ(b.scene.name, a.scene.name);
  EXPECT_EQ(b.scene.frame.epsg(), a.scene.frame.epsg());
  EXPECT_EQ(b.scene.bathymetry.geometry().cols, a.scene.bathymetry.geometry().cols);
  EXPECT_EQ(b.scene.bathymetry.geometry().rows, a.scene.bathymetry.geometry().rows);
  const auto& ha = a.scene.bathymetry.heights();
  const auto& hb = b.scene.bathymetry.heights();
  ASSERT_EQ(hb.size(), ha.size());
  for (std::size_t i = 0; i < ha.size(); ++i) {
    ASSERT_TRUE(hb[i] == ha[i] || (std::isnan(hb[i]) && std::isnan(ha[i]))) << i;
  }
  EXPECT_EQ(b.scene.objects.primitives().size(), a.scene.objects.primitives().size());
  ASSERT_EQ(b.lines.size(), a.lines.size());
  EXPECT_EQ(b.config.seed, a.config.seed);
  EXPECT_EQ(b.config.sonar.max_range_m, a.config.sonar.max_range_m);

  // With another base directory the relative BAG is looked for there, and the error says where.
  const fs::path other = fs::path(SONARSYNTH_SAMPLES_DIR) / "no-such-dir" / "deeper";
  const std::string expected =
      (other / "../tests/data/bathymetry/tiny_sr.bag").lexically_normal().string();
  try {
    load_scene_from_string(slurp(file), "text.yaml", other);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(expected + ": no such file"), std::string::npos)
        << e.what();
  }
}

TEST(SceneFromString, MalformedYamlNamesTheGivenName) {
  try {
    load_scene_from_string("a: [1, 2\nb: }", "inline.yaml", ".");
    ADD_FAILURE() << "no error";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("inline.yaml: malformed YAML at line"), std::string::npos)
        << e.what();
  }
}

// The head of the inline scenes below: a generated seabed.
const std::string kFlat = R"(bathymetry:
  generate:
    centre: {lat_deg: -33.9, lon_deg: 151.3}
    size_m: [100, 80]
    cell_m: 0.5
)";

// Found by scene_file_fuzz: a key that is a list (YAML "complex key") was an uncaught yaml-cpp
// conversion error (exit 3 from the CLI); a value of the wrong type where yaml-cpp converts
// directly, too. Both are InputErrors naming the file and the line.
TEST(SceneFromString, KeysAndValuesOfTheWrongTypeAreInputErrors) {
  const auto expect_input_error = [](const std::string& yaml, const std::string& part) {
    expect_input_error_from([&] { load_simulation_from_string(yaml, "inline.yaml", "."); }, yaml,
                            part);
  };
  expect_input_error("? [a, b]\n: 1\n", "inline.yaml: key [a, b] (line 1) is not a plain name");
  expect_input_error(kFlat + "  ? {x: 1}\n  : 2\n",
                     "inline.yaml: bathymetry: key {x: 1} (line 6) is not a plain name");
  expect_input_error(
      kFlat + R"(seabed:
  polygons:
    - coordinates_deg: [[-33.9, 151.3], [-33.9, east], [-33.91, 151.3]]
)",
      "inline.yaml: seabed.polygons[0].coordinates_deg[1][1] = 'east'. Violated constraint: "
      "a finite number");
  expect_input_error(kFlat + "materials:\n  - {name: rust, roughness_rms_m: -0.01}\n",
                     "roughness_rms_m");
  expect_input_error(kFlat + "materials:\n  - {name: rust, roughness_length_m: 0}\n",
                     "roughness_length_m");
}

TEST(SceneFromString, MaterialRoughnessKeysAreRead) {
  const Scene s = load_scene_from_string(R"(bathymetry:
  generate:
    centre: {lat_deg: -33.9, lon_deg: 151.3}
    size_m: [100, 80]
    cell_m: 0.5
materials:
  - {name: rust, roughness_rms_m: 0.012, roughness_length_m: 0.07}
  - {name: steel, texture_shape: 8}
)",
                                         "inline.yaml", ".");
  const Material& rust = s.materials[s.materials.index_of("rust")];
  EXPECT_DOUBLE_EQ(rust.roughness_rms_m, 0.012);
  EXPECT_DOUBLE_EQ(rust.roughness_length_m, 0.07);
  const Material& steel = s.materials[s.materials.index_of("steel")];
  EXPECT_DOUBLE_EQ(steel.texture_shape_nu, 8.0);
  // The other keys keep the built-in steel's values (docs/physics.md §1.11).
  EXPECT_DOUBLE_EQ(
      steel.roughness_rms_m,
      MaterialTable::defaults()[MaterialTable::defaults().index_of("steel")].roughness_rms_m);
  EXPECT_DOUBLE_EQ(
      steel.lambert_mu,
      MaterialTable::defaults()[MaterialTable::defaults().index_of("steel")].lambert_mu);
}

TEST(SceneFromString, MaterialSpecularKeysAreRead) {
  const Scene s = load_scene_from_string(kFlat + R"(materials:
  - {name: rust, specular_reflection_db: -10, specular_rms_slope: 0.25}
  - {name: steel, specular_reflection_db: off}
)",
                                         "inline.yaml", ".");
  const Material& rust = s.materials[s.materials.index_of("rust")];
  EXPECT_DOUBLE_EQ(rust.specular_rho, 0.1);
  EXPECT_DOUBLE_EQ(rust.specular_rms_slope, 0.25);
  EXPECT_EQ(s.materials[s.materials.index_of("steel")].specular_rho, 0.0);
  EXPECT_EQ(s.materials[s.materials.index_of("sand")].specular_rho, 0.0);
  const auto expect_input_error = [](const std::string& yaml, const std::string& part) {
    expect_input_error_from([&] { load_scene_from_string(yaml, "inline.yaml", "."); }, yaml, part);
  };
  expect_input_error(kFlat + "materials:\n  - {name: rust, specular_reflection_db: 3}\n",
                     "specular_reflection_db");
  expect_input_error(kFlat + "materials:\n  - {name: rust, specular_rms_slope: 0}\n",
                     "specular_rms_slope");
}

}  // namespace
}  // namespace sonarsynth
