// SPDX-License-Identifier: MIT
// ROS 2 message definitions and their CDR serialisation (docs/robotics.md). The definitions
// are those of the public packages (marine_acoustic_msgs 2.x, sensor_msgs, geometry_msgs,
// tf2_msgs, std_msgs, builtin_interfaces), fields and constants without the comments.
#include "sonarsynth/formats/mcap/ros2_messages.hpp"

#include <bit>
#include <cstring>

namespace sonarsynth::mcap {
namespace {

constexpr std::string_view kTime = "int32 sec\nuint32 nanosec\n";
constexpr std::string_view kHeader = "builtin_interfaces/Time stamp\nstring frame_id\n";
constexpr std::string_view kVector3 = "float64 x\nfloat64 y\nfloat64 z\n";
constexpr std::string_view kQuaternion = "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n";
constexpr std::string_view kPingInfo =
    "float32 frequency\n"
    "float32 sound_speed\n"
    "float32[] tx_beamwidths\n"
    "float32[] rx_beamwidths\n";
constexpr std::string_view kSonarImageData =
    "bool is_bigendian\n"
    "uint32 DTYPE_UINT8 = 0\n"
    "uint32 DTYPE_INT8 = 1\n"
    "uint32 DTYPE_UINT16 = 2\n"
    "uint32 DTYPE_INT16 = 3\n"
    "uint32 DTYPE_UINT32 = 4\n"
    "uint32 DTYPE_INT32 = 5\n"
    "uint32 DTYPE_UINT64 = 6\n"
    "uint32 DTYPE_INT64 = 7\n"
    "uint32 DTYPE_FLOAT32 = 8\n"
    "uint32 DTYPE_FLOAT64 = 9\n"
    "uint32 dtype\n"
    "uint32 beam_count\n"
    "uint8[] data\n";
constexpr std::string_view kRawSonarImage =
    "std_msgs/Header header\n"
    "marine_acoustic_msgs/PingInfo ping_info\n"
    "float32 sample_rate\n"
    "uint32 samples_per_beam\n"
    "uint32 sample0\n"
    "float32[] tx_delays\n"
    "float32[] tx_angles\n"
    "float32[] rx_angles\n"
    "marine_acoustic_msgs/SonarImageData image\n";
constexpr std::string_view kNavSatStatus =
    "int8 STATUS_NO_FIX = -1\n"
    "int8 STATUS_FIX = 0\n"
    "int8 STATUS_SBAS_FIX = 1\n"
    "int8 STATUS_GBAS_FIX = 2\n"
    "int8 status\n"
    "uint16 SERVICE_GPS = 1\n"
    "uint16 SERVICE_GLONASS = 2\n"
    "uint16 SERVICE_COMPASS = 4\n"
    "uint16 SERVICE_GALILEO = 8\n"
    "uint16 service\n";
constexpr std::string_view kNavSatFix =
    "std_msgs/Header header\n"
    "sensor_msgs/NavSatStatus status\n"
    "float64 latitude\n"
    "float64 longitude\n"
    "float64 altitude\n"
    "float64[9] position_covariance\n"
    "uint8 COVARIANCE_TYPE_UNKNOWN = 0\n"
    "uint8 COVARIANCE_TYPE_APPROXIMATED = 1\n"
    "uint8 COVARIANCE_TYPE_DIAGONAL_KNOWN = 2\n"
    "uint8 COVARIANCE_TYPE_KNOWN = 3\n"
    "uint8 position_covariance_type\n";
constexpr std::string_view kImu =
    "std_msgs/Header header\n"
    "geometry_msgs/Quaternion orientation\n"
    "float64[9] orientation_covariance\n"
    "geometry_msgs/Vector3 angular_velocity\n"
    "float64[9] angular_velocity_covariance\n"
    "geometry_msgs/Vector3 linear_acceleration\n"
    "float64[9] linear_acceleration_covariance\n";
constexpr std::string_view kTransform =
    "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n";
constexpr std::string_view kTransformStamped =
    "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n";
constexpr std::string_view kTfMessage = "geometry_msgs/TransformStamped[] transforms\n";
// sonarsynth's own per-sample truth of one side (docs/robotics.md, "Truth topics"); the ROS 1
// text (formats/rosbag/messages.cpp) has the same constants and fields, with comments.
constexpr std::string_view kSideScanTruth =
    "uint8 CLASS_WATER_COLUMN = 0\n"
    "uint8 CLASS_SEABED = 1\n"
    "uint8 CLASS_OBJECT = 2\n"
    "uint8 CLASS_SHADOW = 3\n"
    "uint8 CLASS_NO_SEABED = 4\n"
    "int32 LABEL_NONE = -1\n"
    "std_msgs/Header header\n"
    "uint32 samples\n"
    "uint8[] sample_class\n"
    "int32[] label\n"
    "float32[] grazing_rad\n"
    "float32[] ground_range_m\n";
// The CLASS_* constants above and in the ROS 1 text are SampleClass's codes.
static_assert(static_cast<int>(SampleClass::water_column) == 0 &&
              static_cast<int>(SampleClass::seabed) == 1 &&
              static_cast<int>(SampleClass::object) == 2 &&
              static_cast<int>(SampleClass::shadow) == 3 &&
              static_cast<int>(SampleClass::no_seabed) == 4);

struct Dependency {
  std::string_view name;  // pkg/Type
  std::string_view text;
};

/// The type's text, then each dependency after the separator rosbag2 writes.
std::string definition(std::string_view text, std::initializer_list<Dependency> deps) {
  std::string out(text);
  for (const Dependency& d : deps) {
    out += "================================================================================\n";
    out += "MSG: ";
    out += d.name;
    out += '\n';
    out += d.text;
  }
  return out;
}

void write_header(CdrWriter& w, const Ros2Header& h) {
  w.i32(h.sec);
  w.u32(h.nanosec);
  w.string(h.frame_id);
}

}  // namespace

CdrWriter::CdrWriter(std::vector<std::uint8_t>& out) : out_(out) {
  out_.resize(4);
  out_[0] = 0x00;  // CDR_LE: plain CDR, little endian
  out_[1] = 0x01;
  out_[2] = 0x00;  // options
  out_[3] = 0x00;
}

void CdrWriter::align(std::size_t n) {
  const std::size_t used = out_.size() - 4;
  const std::size_t pad = (n - used % n) % n;
  out_.insert(out_.end(), pad, std::uint8_t{0});
}

void CdrWriter::put(std::uint64_t v, std::size_t n) {
  align(n);
  for (std::size_t i = 0; i < n; ++i) {
    out_.push_back(static_cast<std::uint8_t>((v >> (8 * i)) & 0xFFu));
  }
}

void CdrWriter::f32(float v) {
  put(std::bit_cast<std::uint32_t>(v), 4);
}
void CdrWriter::f64(double v) {
  put(std::bit_cast<std::uint64_t>(v), 8);
}

void CdrWriter::string(std::string_view s) {
  u32(static_cast<std::uint32_t>(s.size() + 1));
  out_.insert(out_.end(), s.begin(), s.end());
  out_.push_back(0);
}

void CdrWriter::f32_sequence(std::span<const float> values) {
  u32(static_cast<std::uint32_t>(values.size()));
  for (float v : values) f32(v);
}

std::span<std::uint8_t> CdrWriter::u8_sequence(std::size_t n) {
  u32(static_cast<std::uint32_t>(n));
  const std::size_t at = out_.size();
  out_.resize(at + n);
  return std::span<std::uint8_t>(out_.data() + at, n);
}

const Ros2MessageType& raw_sonar_image_type() {
  static const Ros2MessageType t{
      "marine_acoustic_msgs/msg/RawSonarImage",
      definition(kRawSonarImage, {{"std_msgs/Header", kHeader},
                                  {"builtin_interfaces/Time", kTime},
                                  {"marine_acoustic_msgs/PingInfo", kPingInfo},
                                  {"marine_acoustic_msgs/SonarImageData", kSonarImageData}})};
  return t;
}

const Ros2MessageType& nav_sat_fix_type() {
  static const Ros2MessageType t{
      "sensor_msgs/msg/NavSatFix",
      definition(kNavSatFix, {{"std_msgs/Header", kHeader},
                              {"builtin_interfaces/Time", kTime},
                              {"sensor_msgs/NavSatStatus", kNavSatStatus}})};
  return t;
}

const Ros2MessageType& imu_type() {
  static const Ros2MessageType t{"sensor_msgs/msg/Imu",
                                 definition(kImu, {{"std_msgs/Header", kHeader},
                                                   {"builtin_interfaces/Time", kTime},
                                                   {"geometry_msgs/Quaternion", kQuaternion},
                                                   {"geometry_msgs/Vector3", kVector3}})};
  return t;
}

const Ros2MessageType& tf_message_type() {
  static const Ros2MessageType t{
      "tf2_msgs/msg/TFMessage",
      definition(kTfMessage, {{"geometry_msgs/TransformStamped", kTransformStamped},
                              {"std_msgs/Header", kHeader},
                              {"builtin_interfaces/Time", kTime},
                              {"geometry_msgs/Transform", kTransform},
                              {"geometry_msgs/Vector3", kVector3},
                              {"geometry_msgs/Quaternion", kQuaternion}})};
  return t;
}

const Ros2MessageType& side_scan_truth_type() {
  static const Ros2MessageType t{"sonarsynth_msgs/msg/SideScanTruth",
                                 definition(kSideScanTruth, {{"std_msgs/Header", kHeader},
                                                             {"builtin_interfaces/Time", kTime}})};
  return t;
}

std::span<std::uint8_t> write_raw_sonar_image(CdrWriter& w, const RawSonarImageFields& f) {
  write_header(w, f.header);
  w.f32(f.frequency_hz);  // ping_info
  w.f32(f.sound_speed_m_s);
  w.f32_sequence(std::span<const float>(&f.tx_beamwidth_rad, 1));
  w.f32_sequence(std::span<const float>(&f.rx_beamwidth_rad, 1));
  w.f32(f.sample_rate_hz);
  w.u32(f.samples);  // samples_per_beam
  w.u32(0);          // sample0
  const float zero = 0.0f;
  w.f32_sequence(std::span<const float>(&zero, 1));  // tx_delays
  w.f32_sequence(std::span<const float>(&zero, 1));  // tx_angles
  w.f32_sequence(std::span<const float>(&zero, 1));  // rx_angles
  w.boolean(false);                                  // image.is_bigendian
  w.u32(static_cast<std::uint32_t>(f.dtype));
  w.u32(1);  // beam_count
  const std::size_t size = f.dtype == SonarImageDtype::kUint8    ? 1
                           : f.dtype == SonarImageDtype::kUint16 ? 2
                                                                 : 4;
  return w.u8_sequence(std::size_t{f.samples} * size);
}

void write_side_scan_truth(CdrWriter& w, const Ros2Header& h, const SideOutput& side) {
  write_header(w, h);
  const std::size_t n = side.truth_class.size();
  w.u32(static_cast<std::uint32_t>(n));
  const std::span<std::uint8_t> classes = w.u8_sequence(n);
  for (std::size_t i = 0; i < n; ++i) classes[i] = static_cast<std::uint8_t>(side.truth_class[i]);
  w.u32(static_cast<std::uint32_t>(n));
  for (const std::int32_t v : side.truth_label) w.i32(v);
  w.f32_sequence(side.truth_grazing_rad);
  w.f32_sequence(side.truth_ground_range_m);
}

void write_nav_sat_fix(CdrWriter& w, const Ros2Header& h, bool fix, double lat_deg, double lon_deg,
                       double altitude_m) {
  write_header(w, h);
  w.i8(fix ? 0 : -1);  // status.status: STATUS_FIX or STATUS_NO_FIX
  w.u16(1);            // status.service: SERVICE_GPS
  w.f64(lat_deg);
  w.f64(lon_deg);
  w.f64(altitude_m);
  rosbag::put_covariance(w, 0.0);
  w.u8(0);  // COVARIANCE_TYPE_UNKNOWN
}

void write_imu(CdrWriter& w, const Ros2Header& h, const Quaternion& orientation) {
  write_header(w, h);
  rosbag::put_quaternion(w, orientation);
  rosbag::put_covariance(w, 0.0);  // orientation: covariance unknown
  for (int i = 0; i < 3; ++i) w.f64(0.0);
  rosbag::put_covariance(w, -1.0);  // angular velocity not provided
  for (int i = 0; i < 3; ++i) w.f64(0.0);
  rosbag::put_covariance(w, -1.0);  // linear acceleration not provided
}

void write_tf_message(CdrWriter& w, std::int32_t sec, std::uint32_t nanosec,
                      std::span<const Transform> transforms) {
  w.u32(static_cast<std::uint32_t>(transforms.size()));
  for (const Transform& t : transforms) {
    write_header(w, {sec, nanosec, t.parent_frame});
    w.string(t.child_frame);
    w.f64(t.x_m);
    w.f64(t.y_m);
    w.f64(t.z_m);
    rosbag::put_quaternion(w, t.rotation);
  }
}

}  // namespace sonarsynth::mcap
