// SPDX-License-Identifier: MIT
// The live node's throughput and latency (docs/robotics.md, "Latency"; run_benchmark.sh starts
// the master and the node). Drives the node with the poses of the scene's survey (one odometry
// message per ping period, so each yields one ping):
//  1. saturated: N poses published at once; pings/s = N / wall time from the first publish to
//     the N-th starboard image received;
//  2. paced: N poses published at `--times` x the sonar's real-time ping rate c / (2 R); every
//     ping must arrive. Latency per ping: the node's (/sonarsynth/latency: odometry callback to
//     the ping's last message) and end to end (odometry published here -> starboard image
//     received here), median and 99th percentile.
// --waterfall subscribes to the waterfall images too (the node renders them only for a
// subscriber).
// Usage: ros_node_benchmark SCENE [--pings N] [--times X] [--waterfall]
#include <ros/ros.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "bytes_message.hpp"
#include "node_core.hpp"
#include "ros_messages.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using namespace sonarsynth;

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::clamp<std::size_t>(k, 1, v.size()) - 1];
}

ros_node::Odometry odometry(const PingPose& p, std::uint64_t stamp_ns) {
  ros_node::Odometry m;
  m.header.stamp.fromNSec(stamp_ns);
  m.header.frame_id = "odom";
  m.child_frame_id = "base_link";
  m.pose.pose.position.x = p.sensor_xy_m.x();
  m.pose.pose.position.y = p.sensor_xy_m.y();
  m.pose.pose.position.z = p.sensor_z_m;
  // The renderer's heading/pitch/roll as REP 103 yaw/pitch/roll (docs/robotics.md, "Frames").
  const Eigen::Quaterniond q(
      Eigen::AngleAxisd(std::numbers::pi / 2 - p.heading_rad, Eigen::Vector3d::UnitZ()) *
      Eigen::AngleAxisd(-p.pitch_rad, Eigen::Vector3d::UnitY()) *
      Eigen::AngleAxisd(p.roll_rad, Eigen::Vector3d::UnitX()));
  m.pose.pose.orientation.w = q.w();
  m.pose.pose.orientation.x = q.x();
  m.pose.pose.orientation.y = q.y();
  m.pose.pose.orientation.z = q.z();
  m.twist.twist.linear.x = p.speed_m_s;
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "sonarsynth_ros_benchmark", ros::init_options::AnonymousName);
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty()) {
    std::fprintf(stderr, "usage: ros_node_benchmark SCENE [--pings N] [--times X]\n");
    return 2;
  }
  std::uint32_t n = 500;
  double times = 10.0;
  bool waterfall = false;
  for (std::size_t i = 1; i < args.size(); ++i) {
    if (args[i] == "--waterfall") waterfall = true;
    if (i + 1 == args.size()) break;
    if (args[i] == "--pings") n = static_cast<std::uint32_t>(std::stoul(args[i + 1]));
    if (args[i] == "--times") times = std::stod(args[i + 1]);
  }
  SimulationSetup setup = ros_node::load_setup(args[0], {}, {});
  const Survey survey = setup.make_survey();
  const SonarConfig sonar = setup.config.sonar;
  const double period_s = sonar.effective_ping_period_s();
  const auto period_ns = static_cast<std::uint64_t>(std::llround(period_s * 1e9));
  if (survey.total_pings() < 2 * n + 1) {
    std::fprintf(stderr, "ros_node_benchmark: the survey has only %llu pings\n",
                 static_cast<unsigned long long>(survey.total_pings()));
    return 2;
  }

  ros::NodeHandle nh;
  std::vector<Clock::time_point> received;
  std::vector<double> node_latency_s;
  ros::Publisher odom = nh.advertise<ros_node::Odometry>("/odom", 2 * n + 10);
  ros::Subscriber images = nh.subscribe<ros_node::RawSonarImageBytes>(
      "/sonarsynth/sidescan/starboard", 2 * n + 10,
      [&](const ros_node::RawSonarImageBytes::ConstPtr&) { received.push_back(Clock::now()); },
      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  ros::Subscriber latency = nh.subscribe<ros_node::Float64>(
      "/sonarsynth/latency", 2 * n + 10,
      [&](const ros_node::Float64::ConstPtr& m) { node_latency_s.push_back(m->data); });
  std::size_t images_received = 0;
  ros::Subscriber images_sub;
  if (waterfall) {
    images_sub = nh.subscribe<ros_node::Image>(
        "/sonarsynth/waterfall", 10, [&](const ros_node::Image::ConstPtr&) { ++images_received; });
  }
  ros::AsyncSpinner spinner(1);
  spinner.start();
  const auto deadline = Clock::now() + std::chrono::seconds(30);
  while ((odom.getNumSubscribers() == 0 || images.getNumPublishers() == 0 ||
          latency.getNumPublishers() == 0 || (waterfall && images_sub.getNumPublishers() == 0)) &&
         Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const std::uint64_t t0 = 1772359200ull * 1000000000ull;
  const auto wait_for = [&](std::size_t count, double timeout_s) {
    const auto end = Clock::now() + std::chrono::duration<double>(timeout_s);
    while (received.size() < count && Clock::now() < end) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    return received.size() >= count;
  };

  // Pose 0 starts the clock (ping 0); then one pose per period.
  odom.publish(odometry(survey.pose(0, setup.scene.bathymetry), t0));
  if (!wait_for(1, 30.0)) {
    std::fprintf(stderr, "ros_node_benchmark: no ping from the node\n");
    return 1;
  }
  std::printf("scene %s: %g m range, 2 x %zu samples, real-time rate c / (2 R) = %.2f pings/s\n",
              args[0].c_str(), sonar.max_range_m, sonar.samples_per_channel, 1.0 / period_s);

  // 1. Saturated.
  received.clear();
  node_latency_s.clear();
  const auto start = Clock::now();
  for (std::size_t i = 1; i <= n; ++i) {
    odom.publish(odometry(survey.pose(i, setup.scene.bathymetry), t0 + i * period_ns));
  }
  const bool all = wait_for(n, 120.0);
  const double wall_s = std::chrono::duration<double>(received.back() - start).count();
  std::printf("saturated: %zu of %zu pings in %.3f s = %.1f pings/s (%.1f x real time)\n",
              received.size(), std::size_t{n}, wall_s,
              static_cast<double>(received.size()) / wall_s,
              static_cast<double>(received.size()) / wall_s * period_s);

  // 2. Paced at `times` x real time.
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  received.clear();
  node_latency_s.clear();
  std::vector<Clock::time_point> sent;
  const auto step = std::chrono::duration<double>(period_s / times);
  const auto paced_start = Clock::now();
  for (std::size_t i = n + 1; i <= 2 * n; ++i) {
    std::this_thread::sleep_until(paced_start + (i - n - 1) * step);
    sent.push_back(Clock::now());
    odom.publish(odometry(survey.pose(i, setup.scene.bathymetry), t0 + i * period_ns));
  }
  const bool paced_all = wait_for(n, 60.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  std::vector<double> e2e;
  for (std::size_t i = 0; i < std::min(sent.size(), received.size()); ++i) {
    e2e.push_back(std::chrono::duration<double>(received[i] - sent[i]).count());
  }
  const double paced_s = std::chrono::duration<double>(received.back() - paced_start).count();
  std::printf("paced at %.0f x real time (%.1f pings/s): %zu of %zu pings, %.1f pings/s\n", times,
              times / period_s, received.size(), std::size_t{n},
              static_cast<double>(received.size()) / paced_s);
  std::printf(
      "latency per ping, node (odometry callback -> last message): median %.3f ms, "
      "p99 %.3f ms\n",
      1e3 * percentile(node_latency_s, 0.5), 1e3 * percentile(node_latency_s, 0.99));
  std::printf(
      "latency per ping, end to end (odometry published -> image received): median "
      "%.3f ms, p99 %.3f ms\n",
      1e3 * percentile(e2e, 0.5), 1e3 * percentile(e2e, 0.99));
  if (waterfall) std::printf("waterfall images received: %zu\n", images_received);
  spinner.stop();
  return all && paced_all ? 0 : 1;
}
