// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sonarsynth/formats/rosbag/reader.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"

namespace sonarsynth::mcap {

namespace read {
class Cdr;
}

// The pings, attitude samples, image settings and anomalies are those of the ROS 1 bag reader:
// both map the same messages (docs/robotics.md, "Reading bags").
using rosbag::Anomaly;
using rosbag::ImageInfo;
using rosbag::ImuSample;
using rosbag::Ping;

/// One channel of the bag (a topic with its schema), from the summary or the records.
struct ChannelInfo {
  std::uint16_t id = 0;
  std::string topic;
  std::string schema;            ///< schema name, e.g. "sensor_msgs/msg/NavSatFix"; "" = none
  std::string message_encoding;  ///< "cdr" for ROS 2
  std::uint64_t messages = 0;    ///< from the Statistics record, else counted while reading
  /// The reader decodes this channel: a schema it knows with message encoding "cdr".
  bool decoded = false;
};

/// ROS 2 bag reader for MCAP files (docs/robotics.md, "Reading bags"). With a summary it reads
/// the chunk indexes and, per chunk, the message indexes of the channels it decodes; without a
/// summary (footer summary_start = 0) it walks the data section's records. Chunks: zstd or
/// uncompressed, their CRC checked when not 0; the summary CRC too. Channels are found by schema
/// name (RawSonarImage, NavSatFix, Imu, TFMessage) and message encoding "cdr", not by topic. The
/// constructor reads the index and every NavSatFix, Imu and TFMessage; next_ping() then streams
/// the images chunk by chunk. Structural damage (a record or field past its end, a bad CRC, an
/// offset that does not point at its record, lz4 chunks) throws FormatError naming the file,
/// the byte offset and the field; a message that cannot be used (e.g. big-endian CDR) is skipped
/// and reported as an anomaly.
class Reader : public rosbag::BagReaderBase {
 public:
  /// Throws FormatError if the file cannot be opened or is not a readable MCAP file.
  explicit Reader(const std::filesystem::path& path);
  Reader(std::span<const std::uint8_t> bytes, std::string name);
  explicit Reader(std::unique_ptr<xtf::ByteSource> source);

  /// The next ping, in the order its second side appears in the file; false at the end.
  bool next_ping(Ping& ping);

  const std::string& profile() const { return profile_; }
  const std::string& library() const { return library_; }
  /// True when read through the summary's chunk and message indexes, false when the records
  /// were walked (no summary).
  bool indexed() const { return indexed_; }
  std::size_t chunk_count() const { return chunk_count_; }
  const std::vector<ChannelInfo>& channels() const { return channels_; }

  enum class Kind : std::uint8_t { kNone, kImage, kFix, kImu, kTf };
  /// A part of the data section holding messages: a chunk (with its message indexes when
  /// indexed) or a lone Message record.
  struct Block {
    std::uint64_t offset = 0;  ///< of the Chunk or Message record
    std::uint64_t length = 0;  ///< of the record (and, when indexed, its message indexes)
    std::uint64_t chunk_length = 0;
    bool chunk = false;
  };

 private:
  void open();
  void read_summary(std::uint64_t summary_start, std::uint64_t footer_pos, std::uint32_t crc);
  void scan_records(std::uint64_t end);
  void add_schema(std::span<const std::uint8_t> content, std::uint64_t pos);
  void add_channel(std::span<const std::uint8_t> content, std::uint64_t pos);
  void read_block(std::size_t block, bool images);
  std::span<const std::uint8_t> decompress(std::span<const std::uint8_t> chunk, std::uint64_t pos,
                                           bool check_crc);
  void chunk_messages(std::span<const std::uint8_t> records, std::span<const std::uint8_t> indexes,
                      std::size_t block, bool images);
  void message(std::span<const std::uint8_t> record, std::uint64_t chunk_pos, std::uint64_t at,
               std::uint64_t ordinal, bool images);
  void decode(Kind kind, const ChannelInfo& info, read::Cdr& c, bool images);
  void transforms(read::Cdr& c);
  void image(read::Cdr& c, std::uint64_t stamp, std::string_view frame, const ChannelInfo& info,
             bool images);

  std::string profile_, library_;
  bool indexed_ = false;
  std::size_t chunk_count_ = 0;
  std::map<std::uint16_t, std::string> schemas_;  ///< schema id -> name ("" = not ros2msg)
  std::vector<ChannelInfo> channels_;
  std::map<std::uint16_t, std::size_t> by_id_;  ///< channel id -> channels_ index
  std::vector<Kind> kinds_;                     ///< per channels_ entry
  bool count_messages_ = true;                  ///< no Statistics record
  std::vector<Block> blocks_;                   ///< in file order
  std::vector<std::uint8_t> buffer_, chunk_;
  std::vector<std::pair<std::uint64_t, std::uint16_t>> entries_;  ///< message index: offset, ch

  std::uint64_t ordinal_ = 0, offset_ = 0;  ///< of the message being decoded
  std::uint32_t sequence_ = 0;              ///< its Message record's sequence
};

}  // namespace sonarsynth::mcap
