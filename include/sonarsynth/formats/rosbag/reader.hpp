// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sonarsynth/formats/io/sonar_ping.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"

namespace sonarsynth::rosbag {

namespace records {
class Cursor;
}
class PingAssembler;
struct ImageFields;
struct ImageSource;

/// One connection of a bag (a topic with its message type), from the bag's index.
struct ConnectionInfo {
  std::uint32_t id = 0;
  std::string topic;
  std::string type;
  std::string md5sum;
  std::uint64_t messages = 0;  ///< from the chunk info records
  /// The reader decodes this connection: a type it knows (RawSonarImage, NavSatFix, Imu) with
  /// the MD5 sum of docs/rosbag.md.
  bool decoded = false;
};

/// Something the reader skipped and carried on after (a message it cannot use).
struct Anomaly {
  std::uint64_t offset = 0;  ///< byte offset in the file of the message concerned
  std::string message;       ///< "rosbag reader: <file>: ..." naming the field and value
};

/// The PingInfo and image layout of the first side-scan image (docs/rosbag.md).
struct ImageInfo {
  double frequency_hz = 0.0;               ///< 0 = unknown
  double horizontal_beam_width_rad = 0.0;  ///< tx_beamwidths[0]; 0 = unknown
  double vertical_beam_width_rad = 0.0;    ///< rx_beamwidths[0]; 0 = unknown
  std::uint32_t dtype = 2;                 ///< SonarImageData.dtype
  /// Beam-axis depression below horizontal from the first tf2_msgs/TFMessage transform to a
  /// port frame (docs/rosbag.md, "Frames"); 0 = none in the bag.
  double tilt_rad = 0.0;
};

/// One ping: the port and starboard RawSonarImage of the same header.stamp with the navigation
/// and attitude at or before it.
struct Ping {
  SonarPing sonar;              ///< altitude, depth, speed and heave 0: a bag has no field for them
  bool nav_valid = false;       ///< a NavSatFix with status >= 0 at or before the ping
  bool attitude_valid = false;  ///< an Imu with a known orientation at or before the ping
  std::uint64_t offset = 0;     ///< byte offset of the port image's message data record
  std::uint64_t index = 0;      ///< ordinal of the port image among the bag's messages
  std::uint32_t dtype = 2;      ///< SonarImageData.dtype of the port image
};

/// An Imu message's orientation as heading/pitch/roll (docs/rosbag.md, the writer's mapping
/// reversed).
struct ImuSample {
  std::uint64_t stamp_ns = 0;
  std::uint64_t ordinal = 0;  ///< among the bag's messages, in file order
  AttitudeSample attitude;
  bool known = false;  ///< orientation_covariance[0] != -1 and a finite unit quaternion
  bool used = false;   ///< given to a ping by next_ping()
};

/// What the ROS 1 bag reader and the MCAP reader (mcap::Reader) share: the file, the first
/// image's settings, the pings assembled from the navigation, attitude and image messages, and
/// the anomalies.
class BagReaderBase {
 public:
  BagReaderBase(const BagReaderBase&) = delete;
  BagReaderBase& operator=(const BagReaderBase&) = delete;

  const std::string& name() const;
  std::uint64_t file_size() const { return size_; }
  /// Of the first side-scan image and the transforms (read by the constructor); empty if the bag
  /// has no image.
  const std::optional<ImageInfo>& image_info() const { return image_info_; }
  /// Every Imu message sorted by (stamp, ordinal); `used` is set as pings take them.
  const std::vector<ImuSample>& imu() const;
  const std::vector<Anomaly>& anomalies() const { return anomalies_; }
  std::uint64_t total_anomalies() const { return anomaly_count_; }

 protected:
  /// `reader` starts every anomaly ("rosbag reader", then ": <file>: "); `nav_before_images`:
  /// the bag's writer puts a ping's navigation and attitude before its images (MCAP), not after.
  BagReaderBase(std::unique_ptr<xtf::ByteSource> source, std::string_view reader,
                bool nav_before_images);
  ~BagReaderBase();
  /// Counts an anomaly, keeping the first 1000.
  void report(std::uint64_t offset, std::string message);
  /// Keeps the settings of the first image; with `images`, gives the image to the assembler.
  void add_image(const ImageFields& f, const ImageSource& source, bool images);
  /// The next ping of the assembler, reading the images of block after block (`blocks` of them,
  /// chunks in file order) with `read_images(block)` until one is complete; false at the end.
  bool next_assembled_ping(Ping& ping, std::size_t blocks,
                           const std::function<void(std::size_t)>& read_images);

  std::unique_ptr<xtf::ByteSource> source_;
  std::uint64_t size_ = 0;
  std::optional<ImageInfo> image_info_;
  std::optional<double> tilt_rad_;        ///< from the first transform to a port frame
  std::unique_ptr<PingAssembler> pings_;  ///< the NavSatFix and Imu messages, the sides paired
  std::vector<Anomaly> anomalies_;
  std::uint64_t anomaly_count_ = 0;
  std::size_t next_block_ = 0;  ///< the block next_assembled_ping reads next
};

/// ROS 1 bag reader (format 2.0 with its index, uncompressed chunks: docs/rosbag.md, "Reading
/// bags"). Finds the side-scan, navigation and attitude connections by message type (and MD5
/// sum), not by topic, so bags of other sources with the standard messages read too. The
/// constructor reads the index and every NavSatFix and Imu message; next_ping() then streams the
/// images chunk by chunk. Structural damage (a truncated record, a missing header field, an
/// unknown op code, a length past the end, a compressed chunk) throws FormatError naming the
/// file, the byte offset and the field; a message that cannot be used is skipped and reported
/// as an anomaly.
class Reader : public BagReaderBase {
 public:
  /// Throws FormatError if the file cannot be opened or is not an indexed ROS 1 bag 2.0.
  explicit Reader(const std::filesystem::path& path);
  Reader(std::span<const std::uint8_t> bytes, std::string name);
  explicit Reader(std::unique_ptr<xtf::ByteSource> source);

  /// The next ping, in the order its second side appears in the file; false at the end.
  bool next_ping(Ping& ping);

  std::size_t chunk_count() const { return chunks_.size(); }
  const std::vector<ConnectionInfo>& connections() const { return connections_; }

  enum class Kind : std::uint8_t { kNone, kImage, kFix, kImu, kTf };

 private:
  void open();
  void read_index();
  void scan_chunk(std::size_t chunk, bool images);
  void message(std::uint32_t conn, std::span<const std::uint8_t> data, std::uint64_t offset,
               bool images);
  void transforms(records::Cursor& c);
  void image(records::Cursor& c, std::uint32_t seq, std::uint64_t stamp, std::string_view frame,
             const ConnectionInfo& info, std::uint64_t offset, bool images);

  std::vector<ConnectionInfo> connections_;
  std::map<std::uint32_t, std::size_t> by_id_;  ///< connection id -> connections_ index
  std::vector<Kind> kinds_;                     ///< per connections_ entry
  std::vector<std::uint64_t> chunks_;           ///< chunk record positions, ascending
  std::vector<std::uint64_t> chunk_ordinal_;    ///< ordinal of each chunk's first message
  std::vector<std::uint8_t> buffer_;
  std::uint64_t ordinal_ = 0;
};

}  // namespace sonarsynth::rosbag
