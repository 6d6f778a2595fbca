// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "sonarsynth/formats/io/atomic_file.hpp"
#include "sonarsynth/formats/io/sonar_ping.hpp"
#include "sonarsynth/rendered_ping.hpp"

namespace sonarsynth::rosbag {

/// Topics of a sonarsynth bag (docs/rosbag.md).
inline constexpr const char* kPortTopic = "/sonarsynth/sidescan/port";
inline constexpr const char* kStarboardTopic = "/sonarsynth/sidescan/starboard";
inline constexpr const char* kFixTopic = "/sonarsynth/fix";
inline constexpr const char* kImuTopic = "/sonarsynth/imu";
inline constexpr const char* kTfStaticTopic = "/tf_static";
/// The truth topics, only in a bag given truth (Writer::write_truth; docs/robotics.md).
inline constexpr const char* kPortTruthTopic = "/sonarsynth/sidescan/port/truth";
inline constexpr const char* kStarboardTruthTopic = "/sonarsynth/sidescan/starboard/truth";

/// Frames of a sonarsynth bag (docs/rosbag.md, "Frames").
inline constexpr const char* kVehicleFrame = "base_link";
inline constexpr const char* kPortFrame = "sidescan_port";
inline constexpr const char* kStarboardFrame = "sidescan_starboard";

struct WriterOptions {
  /// Sample type of the images: "u16" (0..32767), "u8" (0..255) or "f32": the XTF
  /// encodings (output.sample_format), quantised as the XTF writer does.
  std::string sample_format = "u16";
  double frequency_hz = 0.0;               ///< PingInfo.frequency, Hz, >= 0 (0 = unknown)
  double horizontal_beam_width_rad = 0.0;  ///< along-track -3 dB width, [0, pi) (0 = unknown)
  double vertical_beam_width_rad = 0.0;    ///< across-track -3 dB width, [0, pi) (0 = unknown)
  double tilt_rad = 0.0;                   ///< beam-axis depression below horizontal, [0, pi/2]
  /// "u16" clamps to 0..65535 instead of the XTF writer's 0..32767 (a conversion keeps the
  /// input's values).
  bool u16_full_range = false;
  std::size_t chunk_bytes = 768 * 1024;  ///< a chunk is closed past this size, >= 1
  bool overwrite = false;                ///< replace an existing file
  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// Streaming ROS 1 bag writer (format 2.0, uncompressed chunks, with the index: docs/rosbag.md).
/// Per ping: a marine_acoustic_msgs/RawSonarImage per side, a sensor_msgs/NavSatFix and a
/// sensor_msgs/Imu, all stamped with the ping time; the sonar's frames on /tf_static once,
/// stamped with the first ping's time. The file is written under a temporary name and appears
/// under `path` only when close() succeeds.
class Writer : public SonarFileWriter {
 public:
  /// Throws InputError for invalid options, FormatError if the file cannot be created.
  explicit Writer(std::filesystem::path path, WriterOptions options = {});
  ~Writer();

  /// Appends one ping. Throws InputError naming the field if it cannot be stored (time before
  /// 1970 or past 2106, an empty side, slant range or sound speed not > 0).
  void write_ping(const SonarPing& ping);
  /// Appends an Imu message of `attitude` (an XTF attitude packet).
  void write_attitude(const AttitudeSample& attitude);
  /// Appends one sonarsynth_msgs/SideScanTruth per side of the rendered ping `ping` (after it was
  /// written) on the truth topics, stamped as its RawSonarImage (time, seq, the side's frame).
  /// Throws InputError naming the field unless each side holds truth (all its truth vectors of
  /// one length >= 1). A bag never given truth has no truth connection.
  void write_truth(const SonarPing& ping, const SideOutput& port, const SideOutput& starboard);
  /// Writes the last chunk, the index and the bag header; renames the file into place. Throws
  /// FormatError on failure.
  void close();

  // clipped_samples(): samples that were out of the sample type's range or non-finite and clamped
  // (as XTF).

 private:
  struct ChunkEntry {
    std::uint32_t conn;
    std::uint64_t time_ns;
    std::uint32_t offset;
  };
  struct ChunkInfo {
    std::uint64_t pos;
    std::uint64_t start_ns, end_ns;
    std::vector<std::uint32_t> counts;  ///< messages per connection
  };

  void begin_message(std::uint32_t conn, std::uint64_t time_ns);
  void end_message();
  void write_side(std::uint32_t conn, const SonarPing& p, std::uint64_t time_ns);
  void write_imu(std::uint64_t time_ns, std::uint32_t seq, double heading_true_rad,
                 double pitch_rad, double roll_rad);
  void write_tf_static(std::uint64_t time_ns);
  void flush_chunk();
  void write_file(const std::vector<std::uint8_t>& bytes);

  WriterOptions options_;
  std::ofstream out_;
  std::vector<std::uint8_t> chunk_, record_;
  std::vector<ChunkEntry> entries_;
  std::vector<ChunkInfo> chunks_;
  std::vector<bool> connection_written_;
  std::size_t message_start_ = 0;
  bool tf_written_ = false;
  bool closed_ = false;
  std::uint32_t imu_seq_ = 0;
};

}  // namespace sonarsynth::rosbag
