// SPDX-License-Identifier: MIT
// The override flags of `simulate` are those the option table declares (docs/scene-format.md,
// "Defaults and declarations"): the CLI takes each, and effective.yaml records the options each
// overrides, with the values the library resolves for the same overrides.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <map>
#include <set>

#include "cli_test_util.hpp"
#include "sonarsynth/formats/config/option_table.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

// A flat seabed, one short line; no key the flags override is given.
constexpr const char* kScene = R"(
name: flags
bathymetry:
  generate: {centre: {lat_deg: 43.0, lon_deg: 5.0}, size_m: [80, 80], cell_m: 0.5, depth_m: 12}
survey:
  speed_m_s: 2.0
  altitude_m: 4
  lines:
    - {name: L1, waypoints: [{east_m: -3, north_m: 0}, {east_m: 3, north_m: 0}]}
sonar: {frequency_khz: 600}
noise: {model: none}
)";

// A value for each flag, within the bounds of the options it overrides.
const std::map<std::string, std::string> kValues = {
    {"seed", "12345678901234"}, {"range", "17.5"}, {"samples", "321"}, {"quality", "high"}};

// The node at the key path `path` ("render.quality.gauss_points") of `root`, or an undefined one.
YAML::Node at_path(YAML::Node root, const std::string& path) {
  YAML::Node n = root;
  std::size_t from = 0;
  while (true) {
    const std::size_t dot = path.find('.', from);
    const std::string key = path.substr(from, dot == std::string::npos ? dot : dot - from);
    if (!n.IsMap() || !n[key]) return YAML::Node(YAML::NodeType::Undefined);
    n.reset(n[key]);
    if (dot == std::string::npos) return n;
    from = dot + 1;
  }
}

class OverrideFlags : public test::ScratchDirTest {};

TEST_F(OverrideFlags, TheCliTakesEveryTableFlagAndEffectiveYamlRecordsEach) {
  // The flags are the table's, each with a value here (a new flag fails until it has one).
  std::set<std::string> table, listed;
  for (const options::Flag* f : options::flags()) table.insert(std::string(f->name.substr(2)));
  for (const OverrideFlag& f : override_flags()) listed.insert(f.name);
  EXPECT_EQ(listed, table);
  std::set<std::string> with_values;
  for (const auto& [name, value] : kValues) with_values.insert(name);
  ASSERT_EQ(with_values, table);

  const fs::path scene = write("scene.yaml", kScene);
  std::string args = "simulate " + scene.string() + " -o " + (dir_ / "out").string() +
                     " -q --no-mosaic --no-waterfall --no-truth";
  SimulationOverrides overrides;
  for (const auto& [name, value] : kValues) {
    args += " --" + name + " " + value;
    set_override(overrides, name, value);
  }
  const test::CliResult r = test::run_cli(args, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;

  // Each overridden option is in effective.yaml with the value the library resolves for the same
  // overrides; none of them is in the scene file.
  const SimulationSetup want = load_simulation(scene.string(), overrides);
  const YAML::Node given = YAML::LoadFile(scene.string());
  const YAML::Node effective = YAML::LoadFile((dir_ / "out" / "effective.yaml").string());
  std::set<std::string> recorded;
  for (const options::Option& o : options::all()) {
    if (!o.flag) continue;
    SCOPED_TRACE(o.path());
    EXPECT_FALSE(at_path(given, o.path()).IsDefined());
    const YAML::Node n = at_path(effective, o.path());
    ASSERT_TRUE(n.IsDefined());
    EXPECT_EQ(YAML::Dump(n), YAML::Dump(options::emit(o, want)));
    recorded.insert(std::string(o.flag->name.substr(2)));
  }
  EXPECT_EQ(recorded, table);
  // The values given, as effective.yaml holds them.
  EXPECT_EQ(effective["seed"].as<std::string>(), kValues.at("seed"));
  EXPECT_EQ(effective["sonar"]["range_m"].as<double>(), 17.5);
  EXPECT_EQ(effective["sonar"]["samples"].as<int>(), 321);

  // A text that is no value of the flag's type: named, exit 1.
  for (const char* bad : {"--samples -3", "--range 12m", "--seed x"}) {
    const test::CliResult b = test::run_cli(
        "simulate " + scene.string() + " -o " + (dir_ / "bad").string() + " -q " + bad, dir_);
    EXPECT_EQ(b.exit_code, 1) << bad;
    const std::string flag = std::string(bad).substr(0, std::string(bad).find(' '));
    EXPECT_NE(b.err.find(flag + " = '"), std::string::npos) << b.err;
  }
}

}  // namespace
}  // namespace sonarsynth
