// SPDX-License-Identifier: MIT
// The ROS 2 messages of sonarsynth's MCAP bags: their definitions (ros2msg text, embedded as
// the bag's schemas) and their CDR serialisation (docs/robotics.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sonarsynth/formats/rosbag/quaternion.hpp"
#include "sonarsynth/rendered_ping.hpp"

namespace sonarsynth::mcap {

/// Appends one message in ROS 2's CDR: the 4-byte encapsulation header 00 01 00 00 (plain CDR,
/// little endian), then each field little endian, aligned to its own size (at most 8)
/// relative to the first byte after the header (XCDR1, as rmw_fastrtps writes it).
class CdrWriter {
 public:
  /// Clears `out` and writes the encapsulation header into it.
  explicit CdrWriter(std::vector<std::uint8_t>& out);

  void u8(std::uint8_t v) { put(v, 1); }
  void i8(std::int8_t v) { put(static_cast<std::uint8_t>(v), 1); }
  void boolean(bool v) { put(v ? 1u : 0u, 1); }
  void u16(std::uint16_t v) { put(v, 2); }
  void u32(std::uint32_t v) { put(v, 4); }
  void i32(std::int32_t v) { put(static_cast<std::uint32_t>(v), 4); }
  void f32(float v);
  void f64(double v);
  /// u32 length (with the terminating NUL), the characters, NUL.
  void string(std::string_view s);
  /// A float32[] sequence: u32 count, then the values.
  void f32_sequence(std::span<const float> values);
  /// A uint8[] sequence of `n` bytes: u32 count, then the bytes (returned for the caller to
  /// fill).
  std::span<std::uint8_t> u8_sequence(std::size_t n);

 private:
  void align(std::size_t n);
  void put(std::uint64_t v, std::size_t n);

  std::vector<std::uint8_t>& out_;
};

/// One ROS 2 message type: its name as ROS 2 tools write it ("sensor_msgs/msg/NavSatFix") and
/// its full ros2msg definition: the type's own fields, then each type it uses after a line of 80
/// '=' and "MSG: pkg/Type", as rosbag2 embeds them.
struct Ros2MessageType {
  std::string_view name;
  std::string definition;
};

const Ros2MessageType& raw_sonar_image_type();  ///< marine_acoustic_msgs/msg/RawSonarImage
const Ros2MessageType& nav_sat_fix_type();      ///< sensor_msgs/msg/NavSatFix
const Ros2MessageType& imu_type();              ///< sensor_msgs/msg/Imu
const Ros2MessageType& tf_message_type();       ///< tf2_msgs/msg/TFMessage
const Ros2MessageType& side_scan_truth_type();  ///< sonarsynth_msgs/msg/SideScanTruth

/// std_msgs/Header: builtin_interfaces/Time stamp (sec, nanosec), frame_id.
struct Ros2Header {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  std::string_view frame_id;
};

using rosbag::Quaternion;

/// marine_acoustic_msgs/SonarImageData dtype values.
enum class SonarImageDtype : std::uint32_t { kUint8 = 0, kUint16 = 2, kFloat32 = 8 };

/// The fields of one side's marine_acoustic_msgs/RawSonarImage (one beam).
struct RawSonarImageFields {
  Ros2Header header;
  float frequency_hz = 0.0f;
  float sound_speed_m_s = 0.0f;
  float tx_beamwidth_rad = 0.0f;  ///< along-track -3 dB width
  float rx_beamwidth_rad = 0.0f;  ///< across-track (vertical) -3 dB width
  float sample_rate_hz = 0.0f;
  std::uint32_t samples = 0;
  SonarImageDtype dtype = SonarImageDtype::kUint16;
};

/// Serialises a RawSonarImage; returns the image bytes (samples x the dtype's size, little
/// endian, near -> far) for the caller to fill.
std::span<std::uint8_t> write_raw_sonar_image(CdrWriter& w, const RawSonarImageFields& f);

/// sonarsynth_msgs/SideScanTruth of one side's truth (docs/robotics.md, "Truth topics"): the
/// sample count, then per sample the SampleClass code, the label, the grazing angle (rad) and
/// the ground range (m), near -> far. The four truth vectors of `side` must have one length
/// (Writer::write_truth checks).
void write_side_scan_truth(CdrWriter& w, const Ros2Header& h, const SideOutput& side);

/// sensor_msgs/NavSatFix: latitude/longitude in degrees, altitude in metres (NaN = unknown);
/// status STATUS_FIX, or STATUS_NO_FIX when `fix` is false; service SERVICE_GPS; covariance
/// unknown.
void write_nav_sat_fix(CdrWriter& w, const Ros2Header& h, bool fix, double lat_deg, double lon_deg,
                       double altitude_m);

/// sensor_msgs/Imu with only the orientation known (the other two covariances' first element
/// -1, as the message documents for "not provided").
void write_imu(CdrWriter& w, const Ros2Header& h, const Quaternion& orientation);

/// One geometry_msgs/TransformStamped of a TFMessage.
struct Transform {
  std::string_view parent_frame;
  std::string_view child_frame;
  double x_m = 0.0, y_m = 0.0, z_m = 0.0;
  Quaternion rotation;
};

/// tf2_msgs/TFMessage with `transforms`, every one stamped `sec`/`nanosec`.
void write_tf_message(CdrWriter& w, std::int32_t sec, std::uint32_t nanosec,
                      std::span<const Transform> transforms);

}  // namespace sonarsynth::mcap
