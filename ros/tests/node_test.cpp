// SPDX-License-Identifier: MIT
// The live node against a real master (run_node_test.sh starts the master, the node with
// ~samples 256 and ~sonar/frequency_khz 410, and `rosbag record`): a trajectory published on
// /odom yields one ping per sonar period, each side's samples equal to the library's render_ping
// at the pose interpolated to the ping time with the ping's index as noise key, exactly. The
// images are decoded here from their bytes, independently of the codec that wrote them.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "bytes_message.hpp"
#include "node_core.hpp"
#include "ros_messages.hpp"

namespace sonarsynth::ros_node {
namespace {

constexpr std::size_t kSamples = 256;      // the node's ~samples (run_node_test.sh)
constexpr double kFrequencyKhz = 410.0;    // the node's ~sonar/frequency_khz
constexpr std::uint64_t kT0 = 1772359200;  // 2026-03-01T10:00:00Z, seconds
constexpr int kPoses = 21;                 // 10 Hz over 2 s

/// A RawSonarImage decoded from its ROS 1 serialization (marine_acoustic_msgs 2.0).
struct DecodedImage {
  std::uint32_t seq = 0;
  std::uint64_t stamp_ns = 0;
  std::string frame;
  float frequency_hz = 0, sound_speed = 0, sample_rate = 0;
  std::uint32_t samples_per_beam = 0, dtype = 0;
  std::vector<std::uint16_t> samples;
};

class Cursor {
 public:
  explicit Cursor(const std::vector<std::uint8_t>& b) : b_(b) {}
  template <class T>
  T get() {
    if (pos_ + sizeof(T) > b_.size()) throw std::runtime_error("image: truncated");
    T v;
    std::memcpy(&v, b_.data() + pos_, sizeof(T));  // little-endian host (x86-64)
    pos_ += sizeof(T);
    return v;
  }
  std::string str() {
    const auto n = get<std::uint32_t>();
    if (pos_ + n > b_.size()) throw std::runtime_error("image: truncated string");
    std::string s(reinterpret_cast<const char*>(b_.data() + pos_), n);
    pos_ += n;
    return s;
  }
  void skip_f32_array() { pos_ += 4 * get<std::uint32_t>(); }
  bool at_end() const { return pos_ == b_.size(); }

 private:
  const std::vector<std::uint8_t>& b_;
  std::size_t pos_ = 0;
};

DecodedImage decode(const std::vector<std::uint8_t>& bytes) {
  Cursor c(bytes);
  DecodedImage im;
  im.seq = c.get<std::uint32_t>();
  const auto sec = c.get<std::uint32_t>();
  const auto nsec = c.get<std::uint32_t>();
  im.stamp_ns = std::uint64_t{sec} * 1000000000u + nsec;
  im.frame = c.str();
  im.frequency_hz = c.get<float>();
  im.sound_speed = c.get<float>();
  c.skip_f32_array();  // tx_beamwidths
  c.skip_f32_array();  // rx_beamwidths
  im.sample_rate = c.get<float>();
  im.samples_per_beam = c.get<std::uint32_t>();
  EXPECT_EQ(c.get<std::uint32_t>(), 0u);  // sample0
  for (int i = 0; i < 3; ++i) c.skip_f32_array();
  EXPECT_EQ(c.get<std::uint8_t>(), 0u);  // is_bigendian
  im.dtype = c.get<std::uint32_t>();
  EXPECT_EQ(c.get<std::uint32_t>(), 1u);  // beam_count
  const auto n = c.get<std::uint32_t>();
  im.samples.resize(n / 2);
  for (auto& s : im.samples) s = c.get<std::uint16_t>();
  EXPECT_TRUE(c.at_end());
  return im;
}

/// The trajectory: east at 2 m/s along y = 0, 7 m deep, with a yaw, pitch and roll wobble.
std::vector<Odometry> trajectory() {
  std::vector<Odometry> out;
  for (int j = 0; j < kPoses; ++j) {
    Odometry m;
    m.header.seq = static_cast<std::uint32_t>(j);
    m.header.stamp.fromNSec(kT0 * 1000000000u + static_cast<std::uint64_t>(j) * 100000000u);
    m.header.frame_id = "odom";
    m.child_frame_id = "base_link";
    m.pose.pose.position.x = -20.0 + 0.2 * j;
    m.pose.pose.position.y = 0.3 * std::sin(0.5 * j);
    m.pose.pose.position.z = -7.0;
    const Eigen::Quaterniond q(
        Eigen::AngleAxisd(0.05 * std::sin(j), Eigen::Vector3d::UnitZ()) *
        Eigen::AngleAxisd(0.02 * std::cos(j), Eigen::Vector3d::UnitY()) *
        Eigen::AngleAxisd(0.03 * std::sin(2.0 * j), Eigen::Vector3d::UnitX()));
    m.pose.pose.orientation.w = q.w();
    m.pose.pose.orientation.x = q.x();
    m.pose.pose.orientation.y = q.y();
    m.pose.pose.orientation.z = q.z();
    m.twist.twist.linear.x = 2.0;
    out.push_back(m);
  }
  return out;
}

OdomSample sample_of(const Odometry& m) {
  OdomSample s;
  s.stamp_ns = m.header.stamp.toNSec();
  const auto& p = m.pose.pose.position;
  const auto& q = m.pose.pose.orientation;
  s.position_m = {p.x, p.y, p.z};
  s.orientation = Eigen::Quaterniond(q.w, q.x, q.y, q.z);
  s.speed_m_s = m.twist.twist.linear.x;
  return s;
}

/// True once node `publisher` sends every topic of `topics` to node `subscriber` over a live
/// connection (the publisher's bus info, ROS 1 slave API getBusInfo: registering with the master
/// comes before the connection).
bool connected(const std::string& publisher, const std::string& subscriber,
               const std::vector<std::string>& topics) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = publisher;
  if (!ros::master::execute("lookupNode", args, result, payload, false)) return false;
  const std::string uri = static_cast<std::string&>(payload);  // http://host:port/
  const auto host_at = uri.find("://") + 3, colon = uri.rfind(':');
  const std::string host = uri.substr(host_at, colon - host_at);
  const int port = std::stoi(uri.substr(colon + 1));
  XmlRpc::XmlRpcClient client(host.c_str(), port, "/");
  XmlRpc::XmlRpcValue call, info;
  call[0] = ros::this_node::getName();
  if (!client.execute("getBusInfo", call, info) ||
      info.getType() != XmlRpc::XmlRpcValue::TypeArray || static_cast<int&>(info[0]) != 1) {
    return false;
  }
  std::set<std::string> seen;
  XmlRpc::XmlRpcValue& conns = info[2];  // [id, destination, direction, transport, topic, ...]
  for (int i = 0; i < conns.size(); ++i) {
    if (static_cast<std::string&>(conns[i][1]) == subscriber &&
        static_cast<std::string&>(conns[i][2]) == "o") {
      seen.insert(static_cast<std::string&>(conns[i][4]));
    }
  }
  for (const std::string& t : topics) {
    if (!seen.count(t)) return false;
  }
  return true;
}

template <class Pred>
bool wait_for(Pred done, double timeout_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!done()) {
    if (std::chrono::steady_clock::now() > end || !ros::ok()) return false;
    ros::spinOnce();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

TEST(NodeLive, TrajectoryYieldsRenderPingAtTheInterpolatedPoses) {
  if (!std::getenv("ROS_MASTER_URI") || !ros::master::check()) {
    GTEST_SKIP() << "no ROS master (run through run_node_test.sh)";
  }
  ros::NodeHandle nh;
  std::map<std::uint32_t, DecodedImage> port, starboard;
  std::vector<double> latency_s;
  ros::Publisher odom = nh.advertise<Odometry>("/odom", 100);
  const auto keep = [](std::map<std::uint32_t, DecodedImage>& into) {
    return [&into](const RawSonarImageBytes::ConstPtr& m) {
      DecodedImage im = decode(m->bytes);
      into[im.seq] = std::move(im);
    };
  };
  ros::Subscriber sp =
      nh.subscribe<RawSonarImageBytes>("/sonarsynth/sidescan/port", 1000, keep(port));
  ros::Subscriber ss =
      nh.subscribe<RawSonarImageBytes>("/sonarsynth/sidescan/starboard", 1000, keep(starboard));
  ros::Subscriber sl =
      nh.subscribe<Float64>("/sonarsynth/latency", 1000,
                            [&](const Float64::ConstPtr& m) { latency_s.push_back(m->data); });
  ASSERT_TRUE(wait_for(
      [&] {
        return odom.getNumSubscribers() > 0 && sp.getNumPublishers() > 0 &&
               ss.getNumPublishers() > 0 && sl.getNumPublishers() > 0;
      },
      30.0))
      << "the node did not connect";
  if (const char* recorder = std::getenv("SONARSYNTH_ROS_TEST_RECORDER")) {
    ASSERT_TRUE(wait_for(
        [&] {
          return connected("/sonarsynth_ros", recorder,
                           {"/sonarsynth/sidescan/port", "/sonarsynth/sidescan/starboard",
                            "/sonarsynth/fix", "/sonarsynth/imu"});
        },
        30.0))
        << "rosbag record did not subscribe";
  }

  const std::vector<Odometry> traj = trajectory();
  for (const auto& m : traj) odom.publish(m);

  // The reference: the same scene and parameters through the library.
  const std::string scene = std::getenv("SONARSYNTH_ROS_TEST_SCENE");
  SimulationSetup setup = load_setup(
      scene, {{"sonar.samples", std::to_string(kSamples)}, {"sonar.frequency_khz", "410"}}, {});
  const double period_s = setup.config.sonar.effective_ping_period_s();
  const auto period_ns = static_cast<std::uint64_t>(std::llround(period_s * 1e9));
  const std::uint64_t span_ns = traj.back().header.stamp.toNSec() - traj[0].header.stamp.toNSec();
  const std::size_t expected = static_cast<std::size_t>(span_ns / period_ns) + 1;
  EXPECT_EQ(expected, 51u);  // 30 m: 2 R / c = 40 ms over 2 s
  const auto sim = make_simulator(setup);

  ASSERT_TRUE(wait_for(
      [&] {
        return port.size() >= expected && starboard.size() >= expected &&
               latency_s.size() >= expected;
      },
      30.0))
      << port.size() << " port, " << starboard.size() << " starboard images of " << expected;
  wait_for([] { return false; }, 0.3);  // nothing more may come
  ASSERT_EQ(port.size(), expected);
  ASSERT_EQ(starboard.size(), expected);
  ASSERT_EQ(latency_s.size(), expected);
  for (double l : latency_s) EXPECT_TRUE(l >= 0.0 && l < 10.0) << l;

  auto ws = sim->make_workspace();
  RenderedPing ref;
  std::size_t j = 0;
  for (std::uint32_t k = 0; k < expected; ++k) {
    const std::uint64_t t = traj[0].header.stamp.toNSec() + k * period_ns;
    while (j + 2 < traj.size() && traj[j + 1].header.stamp.toNSec() < t) ++j;
    const OdomSample pose = interpolate(sample_of(traj[j]), sample_of(traj[j + 1]), t);
    sim->render_ping(ping_pose(pose, k, sim->scene().bathymetry), *ws, ref);
    for (const auto* side : {&port, &starboard}) {
      ASSERT_TRUE(side->count(k)) << "ping " << k;
      const DecodedImage& im = side->at(k);
      const bool stbd = side == &starboard;
      EXPECT_EQ(im.stamp_ns, t) << k;
      EXPECT_EQ(im.frame, stbd ? "sidescan_starboard" : "sidescan_port");
      EXPECT_EQ(im.frequency_hz, static_cast<float>(kFrequencyKhz * 1e3));
      EXPECT_EQ(im.dtype, 2u);  // DTYPE_UINT16
      EXPECT_EQ(im.samples_per_beam, kSamples);
      EXPECT_FLOAT_EQ(im.sample_rate,
                      static_cast<float>(kSamples * setup.config.sonar.sound_speed_m_s / 60.0));
      const std::vector<float>& want = stbd ? ref.starboard.samples : ref.port.samples;
      ASSERT_EQ(im.samples.size(), want.size());
      std::size_t differ = 0;
      for (std::size_t i = 0; i < want.size(); ++i) {
        differ += static_cast<float>(im.samples[i]) != want[i] ? 1u : 0u;
      }
      EXPECT_EQ(differ, 0u) << "ping " << k << (stbd ? " starboard" : " port");
    }
  }
  if (const char* out = std::getenv("SONARSYNTH_ROS_TEST_OUT")) {
    std::ofstream(std::string(out) + "/pings.txt") << expected << "\n";
  }
}

}  // namespace
}  // namespace sonarsynth::ros_node

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "sonarsynth_ros_test", ros::init_options::AnonymousName);
  return RUN_ALL_TESTS();
}
