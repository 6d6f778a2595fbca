// SPDX-License-Identifier: MIT
// The truth topics of the ROS bags (output.bag_truth, docs/robotics.md "Truth topics"), read by
// independent readers with the definitions embedded in the files: the npm MCAP reader
// (tests/mcap_reader/read_bag.js: @mcap/core, @foxglove/rosmsg2-serialization) and Debian's
// python3-rosbag (tests/rosbag_truth.py: genpy's classes generated from the connection's
// definition, their MD5 sums computed by genpy). Every value is compared with the truth the
// library renders for the same survey (Simulator::run, outside `simulate`).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "bag_run_test_util.hpp"
#include "error_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/run_simulation.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"
#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

/// Keeps every rendered ping's two sides.
class Capture : public PingSink {
 public:
  void ping(const RenderedPing& p) override { pings.push_back(p); }
  std::vector<RenderedPing> pings;
};

// The bag tests' line crossing a pipe and passing a rock to port (north): the truth holds
// seabed, object (labels 3 and 5), shadow and water column samples.
class BagTruthTest : public test::BagRunTest {
 protected:
  BagTruthTest()
      : BagRunTest("bag_truth_", test::bag_scene("bag-truth", R"(objects:
  - {type: pipe, id: 3, start: {east_m: 0, north_m: -30}, end: {east_m: 0, north_m: 30}, diameter_m: 0.4}
  - {type: rock, id: 5, position: {east_m: 2, north_m: 8}, diameter_m: 1.2}
)")) {}
  /// The pings of the scene as the library renders them (the run's simulator, set up as
  /// run_simulation does, rendering into a sink of ours).
  std::vector<RenderedPing> render_reference() {
    const SimulationSetup setup = load_simulation(write_scene("").string());
    const Survey survey = setup.make_survey();
    const Simulator sim(setup.scene, setup.config, setup.reference_altitude_m,
                        pilot_poses(survey, setup.scene.bathymetry));
    Capture c;
    (void)sim.run(survey, c);
    return c.pings;
  }
  /// Runs `command` (stdout to a file) and parses its JSON output.
  nlohmann::json run_json(const std::string& command) {
    const fs::path json_path = dir_ / "out.json";
    const std::string full = command + " > '" + json_path.string() + "'";
    EXPECT_EQ(std::system(full.c_str()), 0) << full;
    std::ifstream in(json_path);
    return nlohmann::json::parse(in);
  }
};

/// One truth message as a reader printed it (NaN printed as null) equals the side's truth.
void expect_side(const nlohmann::json& m, const SideOutput& s, const std::string& frame,
                 const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(m.at("frame_id"), frame);
  const std::size_t n = s.truth_class.size();
  ASSERT_GT(n, 0u);
  ASSERT_EQ(m.at("samples").get<std::size_t>(), n);
  const auto cls = m.at("sample_class").get<std::vector<int>>();
  const auto label = m.at("label").get<std::vector<std::int32_t>>();
  const nlohmann::json& grazing = m.at("grazing_rad");
  const nlohmann::json& ground = m.at("ground_range_m");
  ASSERT_EQ(cls.size(), n);
  ASSERT_EQ(label.size(), n);
  ASSERT_EQ(grazing.size(), n);
  ASSERT_EQ(ground.size(), n);
  const auto same = [](const nlohmann::json& v, float want) {
    return std::isnan(want) ? v.is_null() : (v.is_number() && v.get<float>() == want);
  };
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(cls[i], static_cast<int>(s.truth_class[i])) << "sample " << i;
    EXPECT_EQ(label[i], s.truth_label[i]) << "sample " << i;
    EXPECT_TRUE(same(grazing[i], s.truth_grazing_rad[i]))
        << "sample " << i << ": " << grazing[i] << " vs " << s.truth_grazing_rad[i];
    EXPECT_TRUE(same(ground[i], s.truth_ground_range_m[i]))
        << "sample " << i << ": " << ground[i] << " vs " << s.truth_ground_range_m[i];
  }
}

/// Every truth message of a reader's `truth` list (in file order) equals the reference pings'
/// truth, port then starboard per ping, and the reference holds every class but no_seabed.
void expect_truth(const nlohmann::json& truth, const std::vector<RenderedPing>& ref) {
  ASSERT_EQ(truth.size(), 2 * ref.size());
  std::vector<bool> seen(5, false);
  for (std::size_t k = 0; k < ref.size(); ++k) {
    const std::string ping = "ping " + std::to_string(k);
    EXPECT_EQ(truth[2 * k].at("topic"), "/sonarsynth/sidescan/port/truth");
    EXPECT_EQ(truth[2 * k + 1].at("topic"), "/sonarsynth/sidescan/starboard/truth");
    expect_side(truth[2 * k], ref[k].port, "sidescan_port", ping + " port");
    expect_side(truth[2 * k + 1], ref[k].starboard, "sidescan_starboard", ping + " starboard");
    for (const SideOutput* s : {&ref[k].port, &ref[k].starboard}) {
      for (const SampleClass c : s->truth_class) seen[static_cast<std::size_t>(c)] = true;
    }
  }
  for (const SampleClass c :
       {SampleClass::water_column, SampleClass::seabed, SampleClass::object, SampleClass::shadow}) {
    EXPECT_TRUE(seen[static_cast<std::size_t>(c)]) << "class " << static_cast<int>(c);
  }
}

// MCAP: the npm reader decodes the truth messages with the schema embedded in the bag (stamp =
// log time, checked by the reader); every value equals the rendered truth.
TEST_F(BagTruthTest, McapTruthReadByTheNpmReaderEqualsTheRenderedTruth) {
  const fs::path modules = SONARSYNTH_MCAP_READER_MODULES;
  if (const std::string why = test::npm_reader_missing(modules); !why.empty()) GTEST_SKIP() << why;
  const fs::path out = simulate("formats: [xtf, mcap], bag_truth: true");
  const nlohmann::json j =
      run_json("NODE_PATH='" + modules.string() + "' node '" + SONARSYNTH_MCAP_READER_SCRIPT +
               "' '" + (out / "a.mcap").string() + "'");
  const std::vector<RenderedPing> ref = render_reference();
  ASSERT_EQ(j.at("pings").size(), ref.size());
  EXPECT_EQ(j.at("types").at("/sonarsynth/sidescan/port/truth"),
            "sonarsynth_msgs/msg/SideScanTruth");
  EXPECT_EQ(j.at("topics").at("/sonarsynth/sidescan/starboard/truth"), ref.size());
  expect_truth(j.at("truth"), ref);
  // The truth of ping k carries ping k's time.
  for (std::size_t k = 0; k < ref.size(); ++k) {
    EXPECT_EQ(j.at("truth")[2 * k].at("t_us"), j.at("pings")[k].at("t_us"));
  }
}

// ROS 1: python3-rosbag reads the truth messages through genpy's class generated from the
// connection's definition, whose MD5 (computed by genpy) is the connection's md5sum; every value
// equals the rendered truth.
TEST_F(BagTruthTest, RosbagTruthReadByPythonRosbagEqualsTheRenderedTruth) {
  if (std::system("/usr/bin/python3 -c 'import rosbag, genpy' 2>/dev/null") != 0) {
    GTEST_SKIP() << "python3-rosbag is not installed (scripts/install-deps.sh --dev)";
  }
  const fs::path out = simulate("formats: [xtf, rosbag], bag_truth: true");
  const nlohmann::json j =
      run_json(std::string("/usr/bin/python3 '") + SONARSYNTH_ROSBAG_TRUTH_SCRIPT + "' '" +
               (out / "a.bag").string() + "'");
  const std::vector<RenderedPing> ref = render_reference();
  EXPECT_EQ(j.at("types").at("/sonarsynth/sidescan/port/truth"), "sonarsynth_msgs/SideScanTruth");
  EXPECT_EQ(j.at("counts").at("/sonarsynth/sidescan/port"), ref.size());
  expect_truth(j.at("truth"), ref);
}

// Off by default: the bags' topics are the five of before (no truth schema, channel or
// connection), read by the same independent readers.
TEST_F(BagTruthTest, WithoutTheOptionTheBagsHaveNoTruthTopic) {
  const fs::path modules = SONARSYNTH_MCAP_READER_MODULES;
  const bool npm = fs::exists(modules / "@mcap" / "core");
  const bool rosbag = std::system("/usr/bin/python3 -c 'import rosbag, genpy' 2>/dev/null") == 0;
  if (!npm && !rosbag) GTEST_SKIP() << "neither independent reader is installed";
  const fs::path out = simulate("formats: [mcap, rosbag]");
  const nlohmann::json five = {"/sonarsynth/fix", "/sonarsynth/imu", "/sonarsynth/sidescan/port",
                               "/sonarsynth/sidescan/starboard", "/tf_static"};
  if (npm) {
    const nlohmann::json j =
        run_json("NODE_PATH='" + modules.string() + "' node '" + SONARSYNTH_MCAP_READER_SCRIPT +
                 "' '" + (out / "a.mcap").string() + "'");
    nlohmann::json topics = nlohmann::json::array();
    for (const auto& [topic, type] : j.at("types").items()) topics.push_back(topic);
    EXPECT_EQ(topics, five);
    EXPECT_EQ(j.at("schemas").get<std::size_t>(), 4u);
    EXPECT_TRUE(j.at("truth").empty());
  }
  if (rosbag) {
    const nlohmann::json j =
        run_json(std::string("/usr/bin/python3 '") + SONARSYNTH_ROSBAG_TRUTH_SCRIPT + "' '" +
                 (out / "a.bag").string() + "'");
    nlohmann::json topics = nlohmann::json::array();
    for (const auto& [topic, type] : j.at("types").items()) topics.push_back(topic);
    EXPECT_EQ(topics, five);
    EXPECT_TRUE(j.at("truth").empty());
  }
}

// Asked for without the truth it carries, or without a bag to carry it: refused, naming the key.
TEST_F(BagTruthTest, BagTruthWithoutTruthOrBagIsRefused) {
  test::expect_error(
      [&] {
        (void)load_simulation(
            write_scene("formats: [mcap], truth: false, bag_truth: true").string());
      },
      {"output.bag_truth = 'true'", "output.truth: true"}, "truth off");
  test::expect_error(
      [&] { (void)load_simulation(write_scene("formats: [xtf], bag_truth: true").string()); },
      {"output.bag_truth = 'true'", "mcap or rosbag"}, "no bag format");
}

// The readers of sonarsynth ignore the truth topics: the bags with them read as the XTF of the
// run, ping for ping, and `info` lists them as not read.
TEST_F(BagTruthTest, ReadersIgnoreTheTruthTopics) {
  const fs::path out = simulate("formats: [xtf, mcap, rosbag], bag_truth: true");
  for (const auto& [bag, list] :
       {std::pair{"a.mcap", "channels"}, std::pair{"a.bag", "connections"}}) {
    SCOPED_TRACE(bag);
    const std::unique_ptr<SideScanSource> x = SideScanSource::open(out / "a.xtf");
    const std::unique_ptr<SideScanSource> b = SideScanSource::open(out / bag);
    SideScanRecord px, pb;
    std::size_t n = 0;
    while (x->next(px)) {
      ASSERT_TRUE(b->next(pb)) << "ping " << n;
      EXPECT_EQ(pb.sonar.port, px.sonar.port) << "ping " << n;
      EXPECT_EQ(pb.sonar.starboard, px.sonar.starboard) << "ping " << n;
      ++n;
    }
    EXPECT_FALSE(b->next(pb));
    EXPECT_GT(n, 0u);
    EXPECT_EQ(b->total_anomalies(), 0u);
    const SonarFileInfo info = sonar_file_info(out / bag);
    EXPECT_NE(info.text.find("/sonarsynth/sidescan/port/truth"), std::string::npos) << info.text;
    const nlohmann::json j = nlohmann::json::parse(info.json);
    bool listed = false;
    for (const nlohmann::json& c : j.at(list)) {
      if (c.at("topic") != "/sonarsynth/sidescan/starboard/truth") continue;
      listed = true;
      EXPECT_TRUE(c.at("read_as").is_null()) << c;
    }
    EXPECT_TRUE(listed) << info.json;
  }
}

}  // namespace
}  // namespace sonarsynth
