// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "sonarsynth/formats/io/anomaly_log.hpp"
#include "sonarsynth/formats/io/sonar_ping.hpp"
#include "sonarsynth/formats/jsf/records.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"

namespace sonarsynth::jsf {

using xtf::ByteSource;

/// What the reader found wrong in a file. It reports and carries on wherever it can.
enum class AnomalyKind : std::uint8_t {
  kGarbageSkipped,     ///< bytes without a 0x1601 message start, skipped to the next one
  kBadByteCount,       ///< a byte count that is negative or runs past the end of the file
  kOversizedMessage,   ///< message larger than ReaderOptions::max_message_bytes, skipped
  kBadSonarData,       ///< message 80 shorter than 240 + its samples, or unknown data format
  kUnpairedChannel,    ///< a port or starboard message without its other side
  kInvalidTime,        ///< a ping time that is not a valid date/time
  kTimeBackwards,      ///< a ping earlier than the previous valid ping time
  kZeroNavigation,     ///< no position: coordinates 0, out of range, or not units 2
  kOtherSubsystem,     ///< sonar data of a subsystem other than the one read as pings
  kSoundSpeedAssumed,  ///< sound speed NaN, infinite or <= 0: 1500 m/s assumed for the range
  kBadWeighting,       ///< weighting factor whose 2^-N scaling underflows or overflows float
  kBadRange,           ///< sample interval 0, or a slant range over kMaxPlausibleSlantRange_m
};
inline constexpr std::size_t kAnomalyKindCount = 12;
const char* anomaly_kind_name(AnomalyKind kind);

struct Anomaly {
  AnomalyKind kind{};
  std::uint64_t offset = 0;         ///< byte offset of the message (or garbage) concerned
  std::string message;              ///< "jsf reader: ..." with file, message, field and value
  std::uint64_t message_index = 0;  ///< 0-based among the messages with a valid header
};

struct ReaderOptions {
  /// Messages larger than this are reported and skipped without being read, bytes (>= 256).
  std::uint64_t max_message_bytes = std::uint64_t{64} << 20;
  /// At most this many anomaly messages are kept (all are counted).
  std::size_t max_anomaly_messages = 1000;
  /// Subsystem whose sonar data next_ping() assembles; -1 = the first side-scan subsystem
  /// (20..22) seen, or the first subsystem of any sonar data if there is no side scan.
  int subsystem = -1;
  void validate() const;
};

enum class MessageKind : std::uint8_t {
  kSonar,
  kSystemInformation,
  kPitchRoll,
  kXtfPingFields,  ///< message 9999 of sonarsynth's conversion (docs/jsf.md §1.4)
  kOther
};

/// One message. Only the members matching `kind` are filled.
struct Message {
  MessageKind kind = MessageKind::kOther;
  MessageHeader header;
  std::uint64_t offset = 0;  ///< of the 16-byte header
  std::uint64_t index = 0;   ///< 0-based among the file's messages
  SonarDataHeader sonar;     ///< kSonar
  /// kSonar: samples in file order (near -> far on both sides), value = stored x 2^-N;
  /// envelope data (format 0) read as unsigned 16-bit, complex formats as the magnitude.
  std::vector<float> samples;
  SystemInformation system;  ///< kSystemInformation
  AttitudeSample attitude;   ///< kPitchRoll
  XtfPingFields xtf_ping;    ///< kXtfPingFields
};

/// A ping of one subsystem: its port and starboard messages assembled.
struct Ping {
  std::uint8_t subsystem = 0;
  std::uint64_t offset = 0;  ///< of the first message of the ping
  std::uint64_t index = 0;   ///< message index of the first message of the ping
  SonarDataHeader header;    ///< of the first message (port, if present)
  /// SI view: time, position, attitude, altitude, depth, speed, sound speed, slant range
  /// (c n dt / 2), port/starboard near -> far (a missing side is empty).
  SonarPing sonar;
  double layback_m = 0.0;
  bool time_valid = false;
  bool nav_valid = false;  ///< coordinate units 2, not both 0, within +-180 / +-90
  /// The XTF header fields a conversion carried for this ping (message 9999 of the same ping
  /// number before it, docs/jsf.md §1.4).
  std::optional<XtfPingFields> xtf_fields;
};

/// Streaming JSF reader for files from any EdgeTech system: unknown message types are skipped
/// by their byte count, the reader resynchronises on 0x1601 after garbage or a wrong byte
/// count, a truncated last message is reported and the rest kept. Memory is bounded by the
/// largest message (<= max_message_bytes); every size is checked against the file size.
class Reader : public AnomalyLog<Anomaly, kAnomalyKindCount> {
 public:
  /// Throws FormatError if the file cannot be opened or does not start with a message header
  /// (bytes 01 16): not a JSF file.
  explicit Reader(const std::filesystem::path& path, ReaderOptions options = {});
  Reader(std::span<const std::uint8_t> bytes, std::string name, ReaderOptions options = {});
  explicit Reader(std::unique_ptr<ByteSource> source, ReaderOptions options = {});
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  const std::string& name() const;
  std::uint64_t file_size() const { return size_; }

  /// Reads the next message. Returns false at the end. Throws only on I/O errors.
  bool next(Message& message);
  /// Reads messages up to the next ping of the selected subsystem (ReaderOptions::subsystem).
  /// Other messages are counted (message_counts()) and pitch/roll messages kept as
  /// last_attitude(). Returns false at the end.
  bool next_ping(Ping& ping);

  /// Messages read so far, by type.
  const std::map<std::uint16_t, std::uint64_t>& message_counts() const { return counts_; }
  /// Sonar data messages read so far, by subsystem and channel.
  const std::map<std::uint8_t, std::map<std::uint8_t, std::uint64_t>>& sonar_counts() const {
    return sonar_counts_;
  }
  /// The first system information message, if any was read.
  const std::optional<SystemInformation>& system_information() const { return system_; }
  /// The XTF file fields a conversion carried in that message's vendor bytes, if any.
  const std::optional<XtfFileFields>& xtf_file_fields() const { return xtf_file_; }
  /// The subsystem next_ping() reads (-1 until the first sonar data message is seen).
  int subsystem() const { return subsystem_; }

 private:
  void open();
  void report(AnomalyKind kind, std::uint64_t offset, std::string message);
  bool plausible_header_at(std::uint64_t offset, MessageHeader& header);
  std::uint64_t find_next_message(std::uint64_t from);
  bool assemble_ping(Ping& ping);  ///< next_ping() without the carried XTF fields
  bool decode_sonar(std::span<const std::uint8_t> body, Message& m);
  /// Moves the messages' samples into `ping` (the messages are not read again).
  void make_ping(Message* port, Message* starboard, Ping& ping);
  std::string where(const Message& m) const;

  std::unique_ptr<ByteSource> source_;
  ReaderOptions options_;
  std::uint64_t size_ = 0;
  std::uint64_t pos_ = 0;
  std::vector<std::uint8_t> buffer_;
  std::vector<std::uint8_t> scan_buffer_;
  std::map<std::uint16_t, std::uint64_t> counts_;
  std::map<std::uint8_t, std::map<std::uint8_t, std::uint64_t>> sonar_counts_;
  std::optional<SystemInformation> system_;
  std::optional<XtfFileFields> xtf_file_;
  std::optional<XtfPingFields> carried_;  ///< the last message 9999 not yet given to a ping
  int subsystem_ = -1;
  std::uint64_t messages_ = 0;
  Message pending_;  ///< a port message waiting for its starboard
  bool have_pending_ = false;
  Message current_;
  bool have_last_time_ = false;
  UtcTime last_time_{};
};

}  // namespace sonarsynth::jsf
