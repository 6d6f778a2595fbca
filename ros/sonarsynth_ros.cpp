// SPDX-License-Identifier: MIT
// sonarsynth_ros: the live ROS 1 side-scan node (docs/robotics.md, "The live ROS 1 node").
// Subscribes to the vehicle's nav_msgs/Odometry, renders a ping per sonar period at the pose
// interpolated to the ping time and publishes it as a sonarsynth bag holds it (the bag codec's
// message bytes), with a waterfall image and the latency of each ping.
#include <ros/ros.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bytes_message.hpp"
#include "node_core.hpp"
#include "ros_messages.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/rosbag/message_bytes.hpp"
#include "sonarsynth/formats/rosbag/writer.hpp"
#include "sonarsynth/formats/xtf/survey_writer.hpp"

namespace sonarsynth::ros_node {
namespace {

using Clock = std::chrono::steady_clock;

/// The node's parameters (docs/robotics.md, "Parameters").
struct Settings {
  std::string scene;
  OptionValues values;
  SimulationOverrides overrides;
  double max_pose_gap_s = 1.0;
  int queue_size = 1000;
  int waterfall_rows = 256;
  int waterfall_every = 10;
  std::string waterfall_colormap = "black_brown_yellow";
  double stats_every_s = 10.0;
};

/// Parameter `name` of `pnh` as YAML scalar text, or nothing if it is not set.
std::optional<std::string> param_text(const ros::NodeHandle& pnh, const std::string& name) {
  XmlRpc::XmlRpcValue v;
  if (!pnh.getParam(name, v)) return std::nullopt;
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return static_cast<bool&>(v) ? "true" : "false";
    case XmlRpc::XmlRpcValue::TypeInt:
      return std::to_string(static_cast<int&>(v));
    case XmlRpc::XmlRpcValue::TypeDouble: {
      std::ostringstream s;
      s << std::setprecision(17) << static_cast<double&>(v);
      return s.str();
    }
    case XmlRpc::XmlRpcValue::TypeString:
      return static_cast<std::string&>(v);
    default:
      throw InputError("sonarsynth_ros: parameter ~" + name +
                       ": a number, boolean or string expected");
  }
}

Settings read_settings(const ros::NodeHandle& pnh) {
  Settings s;
  if (!pnh.getParam("scene", s.scene) || s.scene.empty()) {
    throw InputError(
        "sonarsynth_ros: parameter ~scene (the scene file, docs/scene-format.md) "
        "is not set");
  }
  for (std::string path : option_paths()) {
    std::string name = path;
    std::replace(name.begin(), name.end(), '.', '/');
    if (auto text = param_text(pnh, name)) s.values.emplace_back(path, *text);
  }
  double range_m = 0.0;
  if (pnh.getParam("range", range_m)) s.overrides.range_m = range_m;
  int samples = 0;
  if (pnh.getParam("samples", samples)) {
    if (samples < 1) {
      throw InputError("sonarsynth_ros: ~samples = " + std::to_string(samples) +
                       ". Violated constraint: >= 1");
    }
    s.overrides.samples = static_cast<std::size_t>(samples);
  }
  std::string quality;
  if (pnh.getParam("quality", quality)) s.overrides.quality = quality;
  pnh.param("max_pose_gap_s", s.max_pose_gap_s, s.max_pose_gap_s);
  pnh.param("queue_size", s.queue_size, s.queue_size);
  pnh.param("waterfall/rows", s.waterfall_rows, s.waterfall_rows);
  pnh.param("waterfall/every", s.waterfall_every, s.waterfall_every);
  pnh.param("waterfall/colormap", s.waterfall_colormap, s.waterfall_colormap);
  pnh.param("stats_every_s", s.stats_every_s, s.stats_every_s);
  const auto at_least_1 = [](const char* name, int v) {
    if (v < 1) {
      throw InputError(std::string("sonarsynth_ros: ~") + name + " = " + std::to_string(v) +
                       ". Violated constraint: >= 1");
    }
  };
  at_least_1("queue_size", s.queue_size);
  at_least_1("waterfall/rows", s.waterfall_rows);
  at_least_1("waterfall/every", s.waterfall_every);
  if (s.waterfall_colormap != "black_brown_yellow" && s.waterfall_colormap != "grey") {
    throw InputError("sonarsynth_ros: ~waterfall/colormap = '" + s.waterfall_colormap +
                     "'. Violated constraint: black_brown_yellow or grey");
  }
  return s;
}

class SonarNode {
 public:
  SonarNode(ros::NodeHandle& nh, Settings s, SimulationSetup setup)
      : settings_(std::move(s)),
        setup_(std::move(setup)),
        sim_(make_simulator(setup_)),
        options_(rosbag::simulation_writer_options(setup_.config.sonar, setup_.sample_format)),
        clock_(setup_.config.sonar.effective_ping_period_s(), settings_.max_pose_gap_s),
        ws_(sim_->make_workspace()),
        waterfall_(
            static_cast<std::size_t>(settings_.waterfall_rows),
            setup_.config.sonar.samples_per_channel,
            settings_.waterfall_colormap == "grey" ? Colormap::grey : Colormap::black_brown_yellow,
            setup_.config.output.max_value) {
    options_.validate();
    const auto queue = static_cast<std::uint32_t>(settings_.queue_size);  // per topic
    port_ = nh.advertise<RawSonarImageBytes>(rosbag::kPortTopic, queue);
    starboard_ = nh.advertise<RawSonarImageBytes>(rosbag::kStarboardTopic, queue);
    fix_ = nh.advertise<NavSatFixBytes>(rosbag::kFixTopic, queue);
    imu_ = nh.advertise<ImuBytes>(rosbag::kImuTopic, queue);
    tf_static_ = nh.advertise<TfMessageBytes>(rosbag::kTfStaticTopic, 1, true);
    image_ = nh.advertise<Image>("/sonarsynth/waterfall", 10);
    latency_ = nh.advertise<Float64>("/sonarsynth/latency", queue);
    odom_ = nh.subscribe("odom", queue, &SonarNode::on_odometry, this,
                         ros::TransportHints().tcpNoDelay());
    start_ = report_start_ = Clock::now();
    ROS_INFO(
        "sonarsynth_ros: %s, ping period %.6g s, range %g m, 2 x %zu samples; odometry on "
        "%s",
        settings_.scene.c_str(), setup_.config.sonar.effective_ping_period_s(),
        setup_.config.sonar.max_range_m, setup_.config.sonar.samples_per_channel,
        odom_.getTopic().c_str());
  }

  /// Logs the pings, rate and latency since the last report (or in total, at shutdown).
  void report(bool total) {
    const double wall_s =
        std::chrono::duration<double>(Clock::now() - (total ? start_ : report_start_)).count();
    const LatencyHistogram& h = total ? all_latency_ : window_latency_;
    const std::uint64_t n = h.count();
    char line[400];
    std::snprintf(
        line, sizeof line,
        "sonarsynth_ros: %s%llu pings published (%.1f pings/s), latency median %.3f ms, "
        "p99 %.3f ms, max %.3f ms; skipped %llu (pose gaps) + %llu (bad poses), refused %llu "
        "odometry messages",
        total ? "in total: " : "", static_cast<unsigned long long>(n),
        wall_s > 0 ? static_cast<double>(n) / wall_s : 0.0, 1e3 * h.quantile(0.5),
        1e3 * h.quantile(0.99), 1e3 * h.max(), static_cast<unsigned long long>(clock_.skipped()),
        static_cast<unsigned long long>(bad_poses_), static_cast<unsigned long long>(refused_));
    if (total) {
      std::printf("%s\n", line);  // after ros::shutdown(), rosconsole no longer prints
      std::fflush(stdout);
    } else {
      ROS_INFO("%s", line);
    }
    window_latency_.clear();
    report_start_ = Clock::now();
  }

 private:
  void on_odometry(const Odometry::ConstPtr& m) {
    const Clock::time_point received = Clock::now();
    OdomSample s;
    s.stamp_ns = m->header.stamp.toNSec();
    const auto& p = m->pose.pose.position;
    const auto& q = m->pose.pose.orientation;
    const auto& v = m->twist.twist.linear;
    s.position_m = {p.x, p.y, p.z};
    s.orientation = Eigen::Quaterniond(q.w, q.x, q.y, q.z);
    s.speed_m_s = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    due_.clear();
    if (!clock_.add(s, due_)) {
      ++refused_;
      ROS_WARN_THROTTLE(5.0,
                        "sonarsynth_ros: odometry stamp %.9f not after the previous one: "
                        "refused",
                        m->header.stamp.toSec());
      return;
    }
    for (const ScheduledPing& d : due_) publish_ping(d, received);
    if (std::chrono::duration<double>(Clock::now() - report_start_).count() >=
        settings_.stats_every_s) {
      report(false);
    }
  }

  void publish_ping(const ScheduledPing& d, Clock::time_point received) {
    const PingPose pose = ping_pose(d.pose, d.index, sim_->scene().bathymetry);
    try {
      check_pose(pose, sim_->scene().bathymetry, "odometry");
    } catch (const InputError& e) {
      ++bad_poses_;
      ROS_WARN_THROTTLE(5.0, "sonarsynth_ros: ping %llu not rendered: %s",
                        static_cast<unsigned long long>(d.index), e.what());
      return;
    }
    sim_->render_ping(pose, *ws_, ping_);
    const SonarPing sp = to_xtf_ping(ping_, sim_->scene().frame, setup_.config.sonar);
    if (!tf_sent_) {
      TfMessageBytes tf;
      rosbag::append_tf_static(tf.bytes, d.time_ns, setup_.config.sonar.tilt_rad);
      tf_static_.publish(tf);
      tf_sent_ = true;
    }
    for (bool starboard : {false, true}) {
      side_.bytes.clear();
      rosbag::append_raw_sonar_image(side_.bytes, sp, starboard, d.time_ns, options_, clipped_);
      (starboard ? starboard_ : port_).publish(side_);
    }
    fix_msg_.bytes.clear();
    rosbag::append_nav_sat_fix(fix_msg_.bytes, sp, d.time_ns);
    fix_.publish(fix_msg_);
    imu_msg_.bytes.clear();
    rosbag::append_imu(imu_msg_.bytes, sp.ping_number, d.time_ns, sp.heading_true_rad, sp.pitch_rad,
                       sp.roll_rad);
    imu_.publish(imu_msg_);
    waterfall_.add(ping_);
    if (++since_image_ >= static_cast<std::uint64_t>(settings_.waterfall_every)) {
      since_image_ = 0;
      if (image_.getNumSubscribers() > 0) publish_waterfall(d.time_ns);
    }
    const double latency_s = std::chrono::duration<double>(Clock::now() - received).count();
    Float64 l;
    l.data = latency_s;
    latency_.publish(l);
    window_latency_.add(latency_s);
    all_latency_.add(latency_s);
  }

  void publish_waterfall(std::uint64_t time_ns) {
    Image img;
    img.header.stamp.fromNSec(time_ns);
    img.header.frame_id = rosbag::kVehicleFrame;
    img.height = static_cast<std::uint32_t>(waterfall_.rows());
    img.width = static_cast<std::uint32_t>(waterfall_.width());
    img.encoding = "rgb8";
    img.is_bigendian = 0;
    img.step = img.width * 3;
    img.data.resize(std::size_t{img.step} * img.height);
    waterfall_.image(img.data.data());
    image_.publish(img);
  }

  Settings settings_;
  SimulationSetup setup_;
  std::shared_ptr<const Simulator> sim_;
  rosbag::WriterOptions options_;
  PingClock clock_;
  Simulator::WorkspacePtr ws_;
  RenderedPing ping_;
  Waterfall waterfall_;
  ros::Publisher port_, starboard_, fix_, imu_, tf_static_, image_, latency_;
  ros::Subscriber odom_;
  std::vector<ScheduledPing> due_;
  RawSonarImageBytes side_;
  NavSatFixBytes fix_msg_;
  ImuBytes imu_msg_;
  bool tf_sent_ = false;
  std::uint64_t since_image_ = 0, bad_poses_ = 0, refused_ = 0, clipped_ = 0;
  LatencyHistogram window_latency_, all_latency_;  // fixed memory (docs/robotics.md, "Latency")
  Clock::time_point start_, report_start_;
};

}  // namespace
}  // namespace sonarsynth::ros_node

int main(int argc, char** argv) {
  using namespace sonarsynth::ros_node;
  ros::init(argc, argv, "sonarsynth_ros");
  ros::NodeHandle nh, pnh("~");
  std::optional<SonarNode> node;
  try {
    Settings s = read_settings(pnh);
    sonarsynth::SimulationSetup setup = load_setup(s.scene, s.values, s.overrides);
    node.emplace(nh, std::move(s), std::move(setup));
  } catch (const std::exception& e) {
    ROS_FATAL("%s", e.what());
    return 1;
  }
  ros::spin();
  node->report(true);
  return 0;
}
