// SPDX-License-Identifier: MIT
// What the ROS 1 bag reader (formats/rosbag/reader.cpp) and the MCAP reader
// (formats/mcap/read_messages.cpp) share once a message is decoded: the RawSonarImage, Imu and
// TFMessage fields after the header (the same in both serialisations, read through either
// cursor), and the pairing of port and starboard images by header.stamp with the navigation and
// attitude at or before each ping (docs/rosbag.md and docs/robotics.md, "Reading bags").
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sonarsynth/formats/rosbag/bag_records.hpp"
#include "sonarsynth/formats/rosbag/reader.hpp"

namespace sonarsynth::rosbag {

inline UtcTime utc_from_ns(std::uint64_t ns) {
  return UtcTime{std::chrono::microseconds{static_cast<std::int64_t>(ns / 1000u)}};
}

/// True if the lower-cased `frame` names a port frame.
bool names_port(std::string_view frame);

/// A RawSonarImage after its header, as read; PingAssembler::add_image checks it.
struct ImageFields {
  ImageInfo info;  ///< frequency, beam widths and dtype; tilt 0
  double sound_speed_m_s = 0.0;
  double sample_rate_hz = 0.0;
  std::uint32_t samples_per_beam = 0;
  std::uint32_t beam_count = 0;
  bool big_endian = false;
  std::span<const std::uint8_t> data;
};

/// The RawSonarImage fields after the header through `c` (records::Cursor or mcap::read::Cdr).
template <class Cursor>
ImageFields read_image_fields(Cursor& c) {
  ImageFields f;
  f.info.frequency_hz = static_cast<double>(c.f32("ping_info.frequency"));
  f.sound_speed_m_s = static_cast<double>(c.f32("ping_info.sound_speed"));
  f.info.horizontal_beam_width_rad = c.first_f32("ping_info.tx_beamwidths");
  f.info.vertical_beam_width_rad = c.first_f32("ping_info.rx_beamwidths");
  f.sample_rate_hz = static_cast<double>(c.f32("sample_rate"));
  f.samples_per_beam = c.u32("samples_per_beam");
  c.u32("sample0");
  c.first_f32("tx_delays");
  c.first_f32("tx_angles");
  c.first_f32("rx_angles");
  f.big_endian = c.u8("image.is_bigendian") != 0;
  f.info.dtype = c.u32("image.dtype");
  f.beam_count = c.u32("image.beam_count");
  f.data = c.take(c.u32("image.data"), "image.data");
  return f;
}

/// The Imu fields after the header through `c`: the orientation as heading/pitch/roll.
template <class Cursor>
ImuSample read_imu(Cursor& c, std::uint64_t stamp_ns, std::uint64_t ordinal) {
  ImuSample s;
  s.stamp_ns = stamp_ns;
  s.ordinal = ordinal;
  s.attitude.time_utc = utc_from_ns(stamp_ns);
  const double x = c.f64("orientation.x"), y = c.f64("orientation.y");
  const double z = c.f64("orientation.z"), w = c.f64("orientation.w");
  const double cov0 = c.f64("orientation_covariance");
  s.known = cov0 != -1.0 && records::attitude_from_quaternion(x, y, z, w, s.attitude);
  return s;
}

/// A TFMessage through `c`, `header(c)` reading a transform's header: sets `tilt_rad` from the
/// first transform to a port frame while it is empty. The writers' port transform: yaw +pi/2,
/// then pitch = tilt about the new y (docs/rosbag.md, "Frames"); the pitch of its ZYX angles is
/// the tilt.
template <class Cursor, class Header>
void read_tilt(Cursor& c, Header header, std::optional<double>& tilt_rad) {
  const std::uint32_t n = c.u32("transforms");
  for (std::uint32_t k = 0; k < n && !tilt_rad; ++k) {
    header(c);
    const bool port = names_port(c.str("transforms.child_frame_id"));
    for (int i = 0; i < 3; ++i) c.f64("transforms.transform.translation");
    const double x = c.f64("transforms.transform.rotation.x");
    const double y = c.f64("transforms.transform.rotation.y");
    const double z = c.f64("transforms.transform.rotation.z");
    const double w = c.f64("transforms.transform.rotation.w");
    AttitudeSample a;
    if (port && records::attitude_from_quaternion(x, y, z, w, a) && a.pitch_rad <= 0.0) {
      tilt_rad = -a.pitch_rad;  // attitude_from_quaternion gives -pitch (nose up)
    }
  }
}

/// Where an image message is and what it is called in anomalies.
struct ImageSource {
  std::uint64_t offset = 0;   ///< the byte offset anomalies carry
  std::uint64_t ordinal = 0;  ///< among the bag's messages, in file order
  std::uint32_t number = 0;   ///< the ping number: header.seq (ROS 1), the record's sequence (MCAP)
  std::uint64_t stamp_ns = 0;
  std::string_view frame, topic, type;
};

/// Pairs the port and starboard images of a bag by header.stamp and gives each ping the
/// NavSatFix and Imu at or before it.
class PingAssembler {
 public:
  /// Where a bag's writer puts a ping's navigation and attitude of the ping's stamp: after its
  /// images (ROS 1 bags) or before them (MCAP).
  enum class NavOrder : std::uint8_t { kAfterImages, kBeforeImages };
  using Report = std::function<void(std::uint64_t offset, std::string message)>;

  /// `prefix` starts every anomaly ("rosbag reader: <file>: ").
  PingAssembler(std::string prefix, NavOrder order, Report report);

  void add_fix(std::uint64_t stamp_ns, std::uint64_t ordinal, std::int8_t status, double lat_deg,
               double lon_deg);
  void add_imu(const ImuSample& s) { imu_.push_back(s); }
  /// After every NavSatFix and Imu is added: sorts them by (stamp, ordinal).
  void sort();
  const std::vector<ImuSample>& imu() const { return imu_; }

  /// Checks an image, skipping (and reporting) one that cannot be used, and pairs it.
  void add_image(const ImageFields& f, const ImageSource& source);
  /// The next complete ping; false if none is ready.
  bool pop(Ping& ping);
  /// At the end of the bag: reports the images without their other side.
  void finish();

 private:
  struct Fix {
    std::uint64_t stamp_ns = 0;
    std::uint64_t ordinal = 0;
    Geodetic position{};
    bool valid = false;
  };
  struct Side {
    std::vector<float> samples;
    std::uint64_t offset = 0, ordinal = 0;
    std::uint32_t number = 0, dtype = 0;
    double sound_speed_m_s = 0.0, slant_range_m = 0.0;
    bool present = false;
  };
  void add_side(Side side, bool port, std::uint64_t stamp_ns);
  void complete(std::uint64_t stamp_ns);
  void unpaired(const Side& s, std::uint64_t stamp_ns);

  std::string prefix_;
  NavOrder order_;
  Report report_;
  std::vector<Fix> fixes_;
  std::vector<ImuSample> imu_;
  std::map<std::uint64_t, std::pair<Side, Side>> pending_;  ///< by stamp: port, starboard
  std::deque<Ping> ready_;
};

}  // namespace sonarsynth::rosbag
