// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string_view>
#include <utility>
#include <vector>

#include "sonarsynth/formats/io/atomic_file.hpp"
#include "sonarsynth/formats/io/sonar_ping.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/rendered_ping.hpp"

namespace sonarsynth::mcap {

/// The bag's topics, in channel id order (1..5; docs/robotics.md): those of the ROS 1 bags
/// (docs/rosbag.md).
inline constexpr std::string_view kPortTopic = "/sonarsynth/sidescan/port";
inline constexpr std::string_view kStarboardTopic = "/sonarsynth/sidescan/starboard";
inline constexpr std::string_view kNavSatTopic = "/sonarsynth/fix";
inline constexpr std::string_view kImuTopic = "/sonarsynth/imu";
inline constexpr std::string_view kTfStaticTopic = "/tf_static";
/// The truth topics (channels 6 and 7), only in a bag written with WriterOptions::truth.
inline constexpr std::string_view kPortTruthTopic = "/sonarsynth/sidescan/port/truth";
inline constexpr std::string_view kStarboardTruthTopic = "/sonarsynth/sidescan/starboard/truth";

/// The frames (docs/robotics.md, as docs/rosbag.md): the vehicle body (x forward, y left, z
/// up: REP 103), whose origin is the navigated point and the transducers, and one frame per
/// side whose x axis is that side's beam axis.
inline constexpr std::string_view kBodyFrame = "base_link";
inline constexpr std::string_view kPortFrame = "sidescan_port";
inline constexpr std::string_view kStarboardFrame = "sidescan_starboard";

struct WriterOptions {
  /// How samples are stored: kUint16 and kUint8 round half up and clamp exactly as the XTF
  /// writer does (the same values as the XTF of the same run), kFloat32 stores them as given.
  xtf::SampleEncoding sample_encoding = xtf::SampleEncoding::kUint16;
  double frequency_hz = 500e3;                           ///< centre frequency, > 0
  double horizontal_beam_width_rad = rad_from_deg(1.0);  ///< along-track, [0, pi)
  double vertical_beam_width_rad = rad_from_deg(50.0);   ///< across-track, [0, pi)
  double tilt_rad = rad_from_deg(20.0);                  ///< beam axis below horizontal
  std::size_t chunk_bytes = std::size_t{4} << 20;        ///< uncompressed, [1 KiB, 1 GiB]
  int zstd_level = 1;                                    ///< [1, 19]
  bool overwrite = false;                                ///< replace an existing file
  /// Declare the truth topics (a sonarsynth_msgs/SideScanTruth schema, two channels) for
  /// write_truth (output.bag_truth, docs/robotics.md "Truth topics"); false: the bag is as
  /// without the option, byte for byte.
  bool truth = false;
  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// Streaming writer of a ROS 2 bag in MCAP (docs/robotics.md): the magic, a Header (profile
/// "ros2"), the four Schemas (ros2msg) and five Channels (cdr), then per ping a
/// sensor_msgs/NavSatFix, a sensor_msgs/Imu and one marine_acoustic_msgs/RawSonarImage per side
/// (the first ping also a tf2_msgs/TFMessage on /tf_static), in zstd Chunks each followed by
/// its MessageIndex records; close() writes DataEnd (with the data section's CRC-32), the
/// summary (Schemas, Channels, Statistics, ChunkIndexes), the SummaryOffsets and the Footer
/// (with the summary CRC). The file appears under `path` only when close() succeeds.
class Writer : public SonarFileWriter {
 public:
  /// Throws InputError for invalid options, FormatError if the file cannot be created.
  explicit Writer(std::filesystem::path path, WriterOptions options = {});
  ~Writer();

  /// Appends one ping (four messages). Throws InputError naming the field if the ping cannot be
  /// stored (empty side, time before 1970 or after 2038, slant range or sound speed not > 0).
  void write_ping(const SonarPing& ping);
  /// Appends a stand-alone attitude sample as a sensor_msgs/Imu on the ping's Imu topic (an XTF
  /// attitude packet in a conversion). Throws InputError naming the field for a time outside
  /// 1970-2038 or a non-finite angle.
  void write_attitude(const AttitudeSample& attitude);
  /// Appends one sonarsynth_msgs/SideScanTruth per side of the rendered ping `ping` (after it was
  /// written), stamped as its RawSonarImage (time, the side's frame). Throws InputError naming
  /// the field unless options.truth and each side holds truth (all its truth vectors of one
  /// length >= 1).
  void write_truth(const SonarPing& ping, const SideOutput& port, const SideOutput& starboard);
  /// Flushes the last chunk, writes the summary and renames the file into place. Throws
  /// FormatError on failure.
  void close();

  std::uint64_t messages_written() const { return messages_written_; }
  // clipped_samples(): samples rounded outside the encoding's range (or non-finite) and clamped, as
  // the XTF writer counts them.

 private:
  struct ChunkIndex;
  struct Zstd;
  static constexpr std::size_t kChannels = 7;  ///< the most channels (with the truth topics)

  struct Ros2Time {
    std::int32_t sec;
    std::uint32_t nanosec;
    std::uint64_t ns;  ///< since 1970, the MCAP log time
  };
  /// `t` as builtin_interfaces/Time; throws InputError naming `field` outside 1970-2038.
  static Ros2Time ros2_time(UtcTime t, const char* field);
  void write_imu_message(std::int32_t sec, std::uint32_t nanosec, std::uint64_t ns,
                         double heading_true_rad, double pitch_rad, double roll_rad);
  void write_start();
  void add_message(std::uint16_t channel, std::uint64_t time_ns);
  void write_side(std::uint16_t channel, const SonarPing& ping, const std::vector<float>& samples,
                  std::int32_t sec, std::uint32_t nanosec);
  void flush_chunk();
  void write_summary();
  void emit(const std::vector<std::uint8_t>& bytes, bool data_section);

  WriterOptions options_;
  std::ofstream out_;
  std::vector<char> stream_buffer_;
  std::unique_ptr<Zstd> zstd_;
  std::vector<std::uint8_t> chunk_;       // uncompressed records of the open chunk
  std::vector<std::uint8_t> message_;     // the CDR message being built
  std::vector<std::uint8_t> record_;      // records on their way to the file
  std::vector<std::uint8_t> compressed_;  // the open chunk, compressed
  std::array<std::vector<std::pair<std::uint64_t, std::uint64_t>>, kChannels> index_;
  std::array<std::uint32_t, kChannels> sequence_{};
  std::array<std::uint64_t, kChannels> channel_messages_{};
  std::vector<ChunkIndex> chunk_indexes_;
  std::uint64_t chunk_start_ns_ = 0, chunk_end_ns_ = 0;
  std::uint64_t start_ns_ = 0, end_ns_ = 0;
  std::uint32_t data_crc_ = 0;
  bool closed_ = false;
  std::uint64_t messages_written_ = 0;
};

}  // namespace sonarsynth::mcap
