// SPDX-License-Identifier: MIT
// What the tests of the bags written by `simulate` share: their scene (one line of about 30 m
// along latitude 43) and a fixture running it in a fresh directory of each test's own.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "sonarsynth/formats/config/run_simulation.hpp"

namespace sonarsynth::test {

/// The scene named `name`: a line of about 30 m along latitude 43 over a generated seabed 12 m
/// deep, with `objects` (a YAML objects section, or "") and no output section.
inline std::string bag_scene(const std::string& name, const std::string& objects) {
  return "\nname: " + name + R"(
seed: 7
bathymetry:
  generate: {centre: {lat_deg: 43.0, lon_deg: 5.0}, size_m: [100, 100], cell_m: 0.5, depth_m: 12}
survey:
  start_time: "2026-03-01T10:00:00Z"
  speed_m_s: 3.0
  altitude_m: 5
  lines:
    - {name: a, waypoints: [{lat_deg: 43.0, lon_deg: 4.9998}, {lat_deg: 43.0, lon_deg: 5.0002}]}
)" + objects +
         "sonar: {frequency_khz: 600, range_m: 20, samples: 300}\n";
}

/// Why the npm MCAP reader (tests/mcap_reader, its packages in `modules`) cannot run, or ""
/// when it is installed.
inline std::string npm_reader_missing(const std::filesystem::path& modules) {
  if (std::filesystem::exists(modules / "@mcap" / "core")) return "";
  return "the npm reader is not installed (" + modules.string() +
         " missing): run tests/mcap_reader/install.sh BUILD_DIR (scripts/test.sh does)";
}

/// A test with a fresh directory `<temp>/sonarsynth_<prefix><test name>` (removed afterwards) in
/// which it runs `scene` with the output sections it chooses.
class BagRunTest : public ::testing::Test {
 protected:
  BagRunTest(std::string prefix, std::string scene)
      : prefix_(std::move(prefix)), scene_(std::move(scene)) {}
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("sonarsynth_" + prefix_ +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  /// Writes the scene with `output` as its output section; returns its path.
  std::filesystem::path write_scene(const std::string& output) {
    const std::filesystem::path scene = dir_ / "scene.yaml";
    std::ofstream(scene) << scene_ << "output: {" << output << "}\n";
    return scene;
  }
  /// Runs the scene with `output` as its output section (no mosaic, waterfall or truth
  /// products); returns the run's directory.
  std::filesystem::path simulate(const std::string& output) {
    const std::filesystem::path scene = write_scene(output);
    RunOptions o;
    o.products.mosaic = false;
    o.products.waterfalls = false;
    o.products.truth = false;
    (void)run_simulation(scene.string(), dir_ / "out", o);
    return dir_ / "out";
  }

  std::filesystem::path dir_;

 private:
  std::string prefix_;
  std::string scene_;
};

}  // namespace sonarsynth::test
