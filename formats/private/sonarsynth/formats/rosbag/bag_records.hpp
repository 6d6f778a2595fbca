// SPDX-License-Identifier: MIT
// The records of a ROS 1 bag (format 2.0) and the serialised message fields, bounds-checked:
// every error is a FormatError naming the file, the byte offset and the field (docs/rosbag.md,
// "Reading bags with sonarsynth"). Used by formats/rosbag/reader.cpp; the writer
// (formats/rosbag/writer.cpp) shares the magic and the op codes.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sonarsynth/formats/io/sonar_ping.hpp"

namespace sonarsynth::rosbag {

/// The first line of a bag (docs/rosbag.md, "File layout").
inline constexpr std::string_view kMagic = "#ROSBAG V2.0\n";
// Record op codes (docs/rosbag.md, "File layout").
inline constexpr std::uint8_t kOpMessageData = 0x02;
inline constexpr std::uint8_t kOpBagHeader = 0x03;
inline constexpr std::uint8_t kOpIndexData = 0x04;
inline constexpr std::uint8_t kOpChunk = 0x05;
inline constexpr std::uint8_t kOpChunkInfo = 0x06;
inline constexpr std::uint8_t kOpConnection = 0x07;
// The message types the reader decodes (docs/rosbag.md, "Reading bags").
inline constexpr std::string_view kImageType = "marine_acoustic_msgs/RawSonarImage";
inline constexpr std::string_view kFixType = "sensor_msgs/NavSatFix";
inline constexpr std::string_view kImuType = "sensor_msgs/Imu";
inline constexpr std::string_view kTfType = "tf2_msgs/TFMessage";

}  // namespace sonarsynth::rosbag

namespace sonarsynth::rosbag::records {

/// Bytes per sample of SonarImageData.dtype 0..9 (uint8 .. float64).
inline constexpr std::array<std::size_t, 10> kDtypeBytes = {1, 1, 2, 2, 4, 4, 8, 8, 4, 8};

/// The little-endian unsigned integer of the `n` (<= 8) bytes at `p`.
inline std::uint64_t le(const std::uint8_t* p, std::size_t n) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < n; ++i) v |= static_cast<std::uint64_t>(p[i]) << (8 * i);
  return v;
}

using Fields = std::vector<std::pair<std::string_view, std::span<const std::uint8_t>>>;

/// A record: its header fields and its data, parsed from a buffer holding it.
struct Record {
  std::uint64_t pos = 0;  ///< file offset of the record
  std::uint8_t op = 0;
  Fields fields;
  std::span<const std::uint8_t> data;
  std::size_t size = 0;  ///< bytes of the whole record
};

/// Throws FormatError "rosbag reader: <file>: byte <pos>: <what>".
[[noreturn]] void fail(const std::string& file, std::uint64_t pos, const std::string& what);

/// Parses a header of `name=value` fields, each with a uint32 length (the record header, and a
/// connection record's data); `pos` is the file offset of `h`.
void parse_fields(std::span<const std::uint8_t> h, std::uint64_t pos, const std::string& file,
                  Fields& fields);
/// Parses the record at buf[at] (file offset base + at). `with_data` = false: the buffer may end
/// after the data length (the data is not looked at).
void parse_record(std::span<const std::uint8_t> buf, std::size_t at, std::uint64_t base,
                  const std::string& file, Record& r, bool with_data = true);
/// The value of header field `name` (of `bytes` bytes unless 0); throws if missing.
std::span<const std::uint8_t> field(const Record& r, std::string_view name, const std::string& file,
                                    std::size_t bytes = 0);
std::uint64_t field_uint(const Record& r, std::string_view name, const std::string& file,
                         std::size_t bytes);
std::string field_str(const Record& r, std::string_view name, const std::string& file);

/// Bounds-checked reading of a message's serialised fields; errors name the field and offset.
class Cursor {
 public:
  Cursor(std::span<const std::uint8_t> d, std::uint64_t offset, const std::string& file,
         std::string_view type)
      : d_(d), offset_(offset), file_(file), type_(type) {}
  std::span<const std::uint8_t> take(std::size_t n, const char* f) {
    if (n > d_.size() - pos_) {
      fail(file_, offset_ + pos_,
           std::string(type_) + "." + f + ": needs " + std::to_string(n) + " bytes, " +
               std::to_string(d_.size() - pos_) + " left in the message");
    }
    pos_ += n;
    return d_.subspan(pos_ - n, n);
  }
  std::uint32_t u32(const char* f) { return static_cast<std::uint32_t>(le(take(4, f).data(), 4)); }
  std::uint8_t u8(const char* f) { return take(1, f)[0]; }
  float f32(const char* f) { return std::bit_cast<float>(u32(f)); }
  double f64(const char* f) { return std::bit_cast<double>(le(take(8, f).data(), 8)); }
  std::string_view str(const char* f) {
    const std::uint32_t n = u32(f);
    const auto s = take(n, f);
    return {reinterpret_cast<const char*>(s.data()), s.size()};
  }
  /// A float32[]: its first element, 0 when empty.
  double first_f32(const char* f) {
    const std::uint32_t n = u32(f);
    if (n > (d_.size() - pos_) / 4) take(std::size_t{n} * 4, f);  // reports the overrun
    const auto s = take(std::size_t{n} * 4, f);
    return n == 0 ? 0.0
                  : static_cast<double>(
                        std::bit_cast<float>(static_cast<std::uint32_t>(le(s.data(), 4))));
  }
  /// std_msgs/Header: returns the stamp in ns; seq and frame_id through the arguments.
  std::uint64_t header(std::uint32_t& seq, std::string_view& frame) {
    seq = u32("header.seq");
    const std::uint32_t sec = u32("header.stamp.secs");
    const std::uint32_t nsec = u32("header.stamp.nsecs");
    if (nsec >= 1000000000u) {
      fail(file_, offset_ + pos_ - 4,
           std::string(type_) + ".header.stamp.nsecs = " + std::to_string(nsec) +
               ". Violated constraint: < 1000000000");
    }
    frame = str("header.frame_id");
    return std::uint64_t{sec} * 1000000000u + nsec;
  }

 private:
  std::span<const std::uint8_t> d_;
  std::size_t pos_ = 0;
  std::uint64_t offset_;
  const std::string& file_;
  std::string_view type_;
};

/// Decodes SonarImageData bytes of `dtype` (< 10) into floats (signed types as signed).
void decode_samples(std::span<const std::uint8_t> bytes, std::uint32_t dtype, bool big_endian,
                    std::vector<float>& out);

/// The heading (clockwise from north), pitch (+ nose up) and roll (+ starboard down) of an ENU
/// orientation of base_link: the writer's yaw = pi/2 - heading, pitch = -pitch, roll = roll
/// reversed (docs/rosbag.md, "sensor_msgs/Imu"). False for a quaternion that is not unit length.
bool attitude_from_quaternion(double x, double y, double z, double w, AttitudeSample& a);

}  // namespace sonarsynth::rosbag::records
