// SPDX-License-Identifier: MIT
// run_simulation, the library entry point behind `sonarsynth simulate`: what it returns agrees
// with what it wrote, and a refused run leaves the output directory as it was.
#include "sonarsynth/formats/config/run_simulation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>

#include "cli_test_util.hpp"
#include "scene_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/jsf/reader.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

const std::string kScene = test::flat_scene("lib-run", 5, 100, 100, 12, 3.0, 5) + R"(
    - {name: a, waypoints: [{lat_deg: 43.0, lon_deg: 4.9998}, {lat_deg: 43.0, lon_deg: 5.0002}]}
    - {name: b, waypoints: [{lat_deg: 43.0001, lon_deg: 5.0002}, {lat_deg: 43.0001, lon_deg: 4.9998}]}
sonar: {frequency_khz: 600, range_m: 20, samples: 400}
)";

class RunSimulationTest : public test::ScratchDirTest {
 protected:
  void SetUp() override {
    ScratchDirTest::SetUp();
    scene_ = (dir_ / "scene.yaml").string();
    std::ofstream(scene_) << kScene;
  }
  std::string scene_;
};

// output.jsf: the JSF of a run holds the XTF's pings: samples equal, navigation within JSF's
// 1/600 000 degree, time within XTF's 10 ms rounding.
TEST_F(RunSimulationTest, JsfAndXtfOfOneRunAgree) {
  std::ofstream(scene_) << kScene << "output: {jsf: true}\n";
  RunOptions o;
  o.products.mosaic = false;
  o.products.waterfalls = false;
  const fs::path out = dir_ / "out";
  const RunResult r = run_simulation(scene_, out, o);
  std::uint64_t total = 0;
  for (const std::string& line : r.line_names) {
    EXPECT_NE(std::find(r.files.begin(), r.files.end(), out / (line + ".jsf")), r.files.end());
    xtf::Reader x(out / (line + ".xtf"));
    jsf::Reader j(out / (line + ".jsf"));
    xtf::Packet p;
    jsf::Ping q;
    while (x.next(p)) {
      if (p.kind != xtf::PacketKind::kPing) continue;
      ASSERT_TRUE(j.next_ping(q));
      const SonarPing& a = p.ping.sonar;
      const SonarPing& b = q.sonar;
      ASSERT_EQ(a.port, b.port) << line << " ping " << a.ping_number;
      ASSERT_EQ(a.starboard, b.starboard);
      EXPECT_EQ(a.ping_number, b.ping_number);
      EXPECT_LE(std::abs(std::chrono::duration<double>(a.time_utc - b.time_utc).count()), 0.006);
      const double half_step = 0.5 / 600000.0 + 1e-12;
      EXPECT_NEAR(deg_from_rad(b.sensor_position.lat_rad), deg_from_rad(a.sensor_position.lat_rad),
                  half_step);
      EXPECT_NEAR(deg_from_rad(b.sensor_position.lon_rad), deg_from_rad(a.sensor_position.lon_rad),
                  half_step);
      EXPECT_NEAR(b.altitude_m, a.altitude_m, 0.0005 + 1e-5);
      EXPECT_NEAR(b.slant_range_m, a.slant_range_m, 1e-4);
      ++total;
    }
    EXPECT_FALSE(j.next_ping(q));
    EXPECT_EQ(j.total_anomalies(), 0u);
  }
  EXPECT_EQ(total, r.total_pings);
  // A second run over the first (overwrite) accepts the .jsf files as its own products.
  o.overwrite = true;
  EXPECT_NO_THROW(run_simulation(scene_, out, o));
}

std::string file_bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// output.formats: [xtf, jsf] and its alias output.jsf: true write the same files, byte for byte;
// output.formats: [jsf] writes JSF alone.
TEST_F(RunSimulationTest, OutputFormatsListAndJsfAliasWriteTheSameFiles) {
  RunOptions o;
  o.products.mosaic = false;
  o.products.waterfalls = false;
  o.products.truth = false;
  const std::string list_scene = (dir_ / "list.yaml").string();
  const std::string jsf_only_scene = (dir_ / "jsf_only.yaml").string();
  std::ofstream(scene_) << kScene << "output: {jsf: true}\n";
  std::ofstream(list_scene) << kScene << "output: {formats: [JSF, xtf]}\n";
  std::ofstream(jsf_only_scene) << kScene << "output: {formats: [jsf]}\n";
  const RunResult alias = run_simulation(scene_, dir_ / "alias", o);
  const RunResult list = run_simulation(list_scene, dir_ / "list", o);
  ASSERT_EQ(alias.files.size(), list.files.size());
  for (const std::string line : {"a", "b"}) {
    for (const std::string ext : {".xtf", ".jsf"}) {
      const std::string a = file_bytes(dir_ / "alias" / (line + ext));
      EXPECT_FALSE(a.empty()) << line + ext;
      EXPECT_EQ(a, file_bytes(dir_ / "list" / (line + ext))) << line + ext;
    }
  }
  // The files in the order of the format list, whatever the order in output.formats.
  EXPECT_EQ(list.files.front().extension(), ".xtf");
  const RunResult jsf_only = run_simulation(jsf_only_scene, dir_ / "jsf_only", o);
  for (const fs::path& f : jsf_only.files) EXPECT_NE(f.extension(), ".xtf") << f;
  EXPECT_TRUE(fs::exists(dir_ / "jsf_only" / "a.jsf"));
  EXPECT_FALSE(fs::exists(dir_ / "jsf_only" / "a.xtf"));
}

TEST_F(RunSimulationTest, UnknownOutputFormatIsANamedErrorListingTheKnownOnes) {
  const auto message = [&](const std::string& output) {
    std::ofstream(scene_) << kScene << "output: " << output << "\n";
    try {
      (void)run_simulation(scene_, dir_ / "out", RunOptions{});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string unknown = message("{formats: [xtf, sdf]}");
  EXPECT_NE(unknown.find("output.formats[1]"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("sdf"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("xtf, jsf"), std::string::npos) << unknown;
  EXPECT_NE(message("{formats: []}").find("output.formats"), std::string::npos);
  EXPECT_NE(message("{formats: [xtf, xtf]}").find("each format once"), std::string::npos);
  EXPECT_NE(message("{formats: [jsf], jsf: false}").find("output.jsf"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(RunSimulationTest, ResultListsWhatWasWrittenAndCountsEveryPing) {
  RunOptions o;
  o.products.mosaic = false;
  std::uint64_t last_done = 0, last_total = 0;
  o.progress = [&](std::uint64_t done, std::uint64_t total) {
    last_done = done;
    last_total = total;
  };
  const fs::path out = dir_ / "out";
  const RunResult r = run_simulation(scene_, out, o);

  std::set<fs::path> listed(r.files.begin(), r.files.end()), present;
  for (const auto& e : fs::directory_iterator(out)) {
    if (e.path().filename() != ".sonarsynth-output") present.insert(e.path());
  }
  EXPECT_EQ(listed, present);
  EXPECT_EQ(r.line_names, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(last_done, r.total_pings);
  EXPECT_EQ(last_total, r.total_pings);
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < r.line_names.size(); ++i) {
    // The statistics count exactly the pings in the line's XTF file.
    xtf::Reader reader(out / (r.line_names[i] + ".xtf"));
    xtf::Packet p;
    std::uint64_t pings = 0;
    while (reader.next(p)) pings += p.kind == xtf::PacketKind::kPing ? 1 : 0;
    EXPECT_EQ(r.line_statistics[i].pings, pings) << r.line_names[i];
    EXPECT_EQ(r.line_statistics[i].samples, pings * 2 * 400);
    sum += pings;
  }
  EXPECT_EQ(sum, r.total_pings);
  EXPECT_EQ(r.plan.total_pings, r.total_pings);
}

TEST_F(RunSimulationTest, RefusedRunsLeaveTheDirectoryAlone) {
  RunOptions o;
  o.products.mosaic = false;
  o.products.waterfalls = false;
  const fs::path out = dir_ / "existing";
  fs::create_directories(out);
  std::ofstream(out / "keep.txt") << "mine";
  EXPECT_THROW(run_simulation(scene_, out, o), Error);  // exists, no overwrite
  EXPECT_TRUE(fs::exists(out / "keep.txt"));
  o.overwrite = true;
  EXPECT_THROW(run_simulation(scene_, dir_, o), Error);  // would delete the scene file
  EXPECT_TRUE(fs::exists(scene_));
}

std::map<std::string, std::string> file_contents(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::ifstream in(e.path(), std::ios::binary);
    out[e.path().filename().string()] =
        std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  return out;
}

// The products are written on threads of their own while the survey renders: every file is the
// same, byte for byte, whatever the number of rendering threads (and so whatever the schedule).
TEST_F(RunSimulationTest, EveryFileIsTheSameForAnyThreadCount) {
  std::map<std::string, std::string> first;
  for (unsigned threads : {1U, 2U, 3U}) {
    RunOptions o;  // every product
    o.overrides.threads = threads;
    const fs::path out = dir_ / ("out" + std::to_string(threads));
    const RunResult r = run_simulation(scene_, out, o);
    const auto files = file_contents(out);
    for (const char* name : {"a.xtf", "b.xtf", "a_waterfall.png", "b_truth.tif", "mosaic.tif",
                             "mosaic_rgb.tif", "truth_mosaic.tif", "effective.yaml"}) {
      EXPECT_TRUE(files.count(name)) << name << " with " << threads << " threads";
    }
    EXPECT_EQ(files.size(), r.files.size() + 1);  // and the directory's marker
    if (first.empty()) {
      first = files;
      continue;
    }
    ASSERT_EQ(files.size(), first.size());
    for (const auto& [name, bytes] : files) {
      EXPECT_TRUE(bytes == first[name]) << name << " differs with " << threads << " threads";
    }
  }
}

// A product thread that fails mid-run (its output directory vanishes under it) fails the run
// with the product's error, and nothing is left that looks like an output.
TEST_F(RunSimulationTest, AFailingProductThreadFailsTheRunAndLeavesNothing) {
  RunOptions o;
  o.overrides.threads = 2;
  bool removed = false;
  o.progress = [&](std::uint64_t done, std::uint64_t total) {
    if (removed || 2 * done < total) return;
    for (const auto& e : fs::directory_iterator(dir_)) {
      if (e.is_directory() && e.path().filename().string().front() == '.') {
        // The product threads keep creating files in it: a removal can meet a file made after
        // it listed the directory ("not empty"); repeat until the directory is gone.
        std::error_code ec;
        for (int attempt = 0; attempt < 1000 && fs::exists(e.path()); ++attempt) {
          fs::remove_all(e.path(), ec);
        }
        removed = !fs::exists(e.path());
      }
    }
  };
  const fs::path out = dir_ / "out";
  EXPECT_THROW(run_simulation(scene_, out, o), Error);
  EXPECT_TRUE(removed);
  EXPECT_FALSE(fs::exists(out));
  std::set<fs::path> left;
  for (const auto& e : fs::directory_iterator(dir_)) left.insert(e.path().filename());
  EXPECT_EQ(left, (std::set<fs::path>{"scene.yaml"}));
}

}  // namespace
}  // namespace sonarsynth
