// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/anomaly_log.hpp"
#include "sonarsynth/formats/io/convert_result.hpp"
#include "sonarsynth/formats/io/sonar_ping.hpp"
#include "sonarsynth/formats/xtf/records.hpp"

namespace sonarsynth::xtf {

/// Random-access bytes the Reader reads from (a file, a memory buffer, or a test's synthetic
/// source). Offsets and sizes are 64-bit.
class ByteSource {
 public:
  virtual ~ByteSource() = default;
  virtual std::uint64_t size() const = 0;
  /// Reads exactly out.size() bytes at `offset` (the caller guarantees offset + size <= size()).
  /// Throws FormatError on an I/O error.
  virtual void read(std::uint64_t offset, std::span<std::uint8_t> out) = 0;
  /// File name or description, for messages.
  virtual const std::string& name() const = 0;
};

/// A file opened read-only (POSIX pread, 64-bit offsets). Throws FormatError if it cannot be
/// opened.
std::unique_ptr<ByteSource> open_file_source(const std::filesystem::path& path);
/// A view of caller-owned memory, which must outlive the source.
std::unique_ptr<ByteSource> memory_source(std::span<const std::uint8_t> bytes,
                                          std::string name = "<memory>");

/// What the reader found wrong in a file. It reports and carries on wherever it can.
enum class AnomalyKind : std::uint8_t {
  kGarbageSkipped,       ///< bytes without a 0xFACE packet start, skipped to the next one
  kBadRecordSize,        ///< NumBytesThisRecord smaller than the record, or past the file end
  kTruncatedPacket,      ///< the last packet ends past the end of the file
  kBadChannel,           ///< ChannelNumber with no CHANINFO, or unsupported sample layout
  kSamplesBeyondRecord,  ///< NumSamples x BytesPerSample runs past NumBytesThisRecord
  kOversizedPacket,      ///< packet larger than ReaderOptions::max_packet_bytes, skipped
  kHeaderChannelCount,   ///< header channel counts disagree with the file's layout
  kInvalidTime,          ///< a ping time that is not a valid date/time
  kTimeBackwards,        ///< a ping earlier than the previous valid ping time
  kZeroNavigation,       ///< a ping whose sensor position is zero, non-finite or out of range
};
inline constexpr std::size_t kAnomalyKindCount = 10;
const char* anomaly_kind_name(AnomalyKind kind);

struct Anomaly {
  AnomalyKind kind{};
  std::uint64_t offset = 0;  ///< byte offset in the file of the packet (or garbage) concerned
  std::string message;       ///< "xtf reader: ..." with file, packet, field and value
  /// 0-based index of the packet concerned among the file's packets with a valid packet header
  /// (the count so far for garbage and record-size anomalies, which precede a packet).
  std::uint64_t packet_index = 0;
};

/// How integer samples are interpreted.
enum class Signedness : std::uint8_t {
  kFromUniPolar,  ///< CHANINFO.UniPolar: 1 = unsigned, 0 = signed (spec)
  kUnsigned,
  kSigned,
};

struct ReaderOptions {
  /// Packets larger than this are reported and skipped without being read, in bytes (>= 64).
  std::uint64_t max_packet_bytes = std::uint64_t{256} << 20;
  /// At most this many anomaly messages are kept (all are counted), so memory stays bounded.
  std::size_t max_anomaly_messages = 1000;
  Signedness signedness = Signedness::kFromUniPolar;
  void validate() const;
};

/// One channel of a sonar packet, samples converted to float.
struct ChannelData {
  XtfPingChanHeader header;
  std::uint8_t type_of_channel = 0;  ///< CHANINFO.TypeOfChannel (ChannelType)
  /// Samples NEAR -> FAR for port and starboard (port is reversed from the file's far -> near
  /// order); in file order for other channel types.
  std::vector<float> samples;
};

/// A decoded sonar packet (HeaderType 0).
struct PingRecord {
  XtfPingHeader header;
  /// Channels in packet order; only the first `channel_count` are valid (capacity is reused).
  std::vector<ChannelData> channels;
  std::size_t channel_count = 0;
  /// Normalised view: SI units, radians; port/starboard = first PORT/STBD channels near -> far.
  /// sensor_position / ship_position are meaningful only if nav_valid and NavUnits == 3.
  SonarPing sonar;
  bool time_valid = false;  ///< date/time fields form a valid time (sonar.time_utc)
  bool nav_valid = false;   ///< sensor X/Y non-zero, finite and (NavUnits 3) within +-180/+-90
};

enum class PacketKind : std::uint8_t { kPing, kNotes, kAttitude, kNavigation, kOther };

/// One packet. Only the member matching `kind` is filled.
struct Packet {
  PacketKind kind = PacketKind::kOther;
  std::uint8_t header_type = 0;
  std::uint64_t offset = 0;      ///< of the packet's first byte
  std::uint32_t size_bytes = 0;  ///< NumBytesThisRecord
  std::uint64_t index = 0;       ///< 0-based among the file's packets (as Anomaly::packet_index)
  PingRecord ping;
  XtfNotesHeader notes;
  XtfAttitudeData attitude;
  XtfHeaderNavigation navigation;
};

/// The neutral attitude sample of an XTF attitude packet (the inverse of Writer::write_attitude):
/// time from SourceEpoch + EpochMicroseconds (clamped to 999999), angles from degrees, heave.
AttitudeSample attitude_sample(const XtfAttitudeData& attitude);

/// Streaming XTF reader for files from any sonar: unknown packet types are skipped, the reader
/// resynchronises on 0xFACE after garbage, samples of 8/16/32-bit integers (signed/unsigned),
/// IEEE and IBM floats are converted to float, port order is normalised to near -> far, more
/// than 6 channels are supported, a truncated last packet is reported and the rest kept.
/// Memory is bounded by the largest packet (<= max_packet_bytes), never by the file size; every
/// size taken from the file is checked in 64-bit arithmetic against the file size.
class Reader : public AnomalyLog<Anomaly, kAnomalyKindCount> {
 public:
  /// Throws FormatError if the file cannot be opened, is shorter than the 1024-byte header or
  /// does not start with FileFormat 0x7B.
  explicit Reader(const std::filesystem::path& path, ReaderOptions options = {});
  /// Over caller-owned memory (which must outlive the Reader).
  Reader(std::span<const std::uint8_t> bytes, std::string name, ReaderOptions options = {});
  explicit Reader(std::unique_ptr<ByteSource> source, ReaderOptions options = {});
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  const XtfFileHeader& file_header() const { return header_; }
  /// Every CHANINFO of the file (the header's six plus any extra blocks), indexed by the ping
  /// channel header's ChannelNumber.
  const std::vector<XtfChanInfo>& chan_info() const { return chan_info_; }
  const std::string& name() const;
  std::uint64_t file_size() const { return size_; }
  /// Offset of the first packet (1024 + extra CHANINFO blocks).
  std::uint64_t data_offset() const { return data_offset_; }

  /// Reads the next packet into `packet` (whose buffers are reused). Returns false at the end.
  /// Broken packets are reported in anomalies() and skipped; throws only on I/O errors.
  bool next(Packet& packet);

 private:
  void open();
  void report(AnomalyKind kind, std::uint64_t offset, std::string message);
  /// The offset of the next plausible packet start at or after `from` (size_ if none).
  std::uint64_t find_next_packet(std::uint64_t from);
  bool plausible_packet_at(std::uint64_t offset);
  bool decode_ping(std::span<const std::uint8_t> bytes, std::uint64_t offset, PingRecord& ping);
  void normalise(PingRecord& ping, std::uint64_t offset);
  /// " (packet K, sonar packet S, PingNumber N) at byte X of FILE" for the current ping.
  std::string ping_where(std::uint32_t ping_number, std::uint64_t offset) const;

  std::unique_ptr<ByteSource> source_;
  ReaderOptions options_;
  std::uint64_t size_ = 0;
  std::uint64_t data_offset_ = 0;
  std::uint64_t pos_ = 0;
  XtfFileHeader header_;
  std::vector<XtfChanInfo> chan_info_;
  std::vector<std::uint8_t> buffer_;
  std::vector<std::uint8_t> scan_buffer_;
  std::uint64_t packets_ = 0;         ///< packets with a valid header read so far
  std::uint64_t sonar_packets_ = 0;   ///< sonar packets (HeaderType 0) among them
  std::uint64_t current_packet_ = 0;  ///< index given to anomalies reported now
  bool have_last_time_ = false;
  UtcTime last_time_{};
};

/// A conversion's reading loop: the next ping packet of `reader` (false at the end). The
/// attitude packets before it are written through `writer.write_attitude` (any format's writer)
/// and counted in `result`, or, where the writer refuses one, skipped with a warning naming it.
template <class Writer>
bool next_ping_copying_attitude(Reader& reader, Packet& packet, Writer& writer,
                                ConvertResult& result) {
  while (reader.next(packet)) {
    if (packet.kind == PacketKind::kPing) return true;
    if (packet.kind != PacketKind::kAttitude) continue;
    try {
      writer.write_attitude(attitude_sample(packet.attitude));
      ++result.attitude_records;
    } catch (const InputError& e) {
      result.warn("attitude packet " + std::to_string(packet.index) + " skipped: " + e.what());
    }
  }
  return false;
}

}  // namespace sonarsynth::xtf
