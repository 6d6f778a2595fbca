// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "sonarsynth/formats/io/atomic_file.hpp"
#include "sonarsynth/formats/io/sonar_ping.hpp"
#include "sonarsynth/formats/xtf/records.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::xtf {

/// How samples are stored. kUint16 is the profile every common reader accepts (docs/xtf.md §5).
enum class SampleEncoding {
  kUint16,   ///< BytesPerSample 2, SampleFormat 3, UniPolar 1, values rounded and clamped to
             ///< 0..32767
  kUint8,    ///< BytesPerSample 1, SampleFormat 8, values rounded and clamped to 0..255
  kFloat32,  ///< BytesPerSample 4, SampleFormat 5 (IEEE), values stored as given
};

/// Largest samples per channel every common reader accepts (MB-System reads at most 16384 bytes
/// per channel).
inline constexpr std::size_t kMaxPortableSamples = 8192;
/// Hard upper bound on samples per channel, even with allow_more_than_8192_samples.
inline constexpr std::size_t kMaxSamples = std::size_t{1} << 20;
/// A latitude or longitude of exactly 0 is written as this many degrees (about 0.1 mm): readers
/// take a zero coordinate as "no position", and the equator and the prime meridian are valid.
inline constexpr double kZeroCoordinateDeg = 1e-9;

/// ProcessingFlags bits (docs/xtf.md §1.6).
inline constexpr std::uint16_t kProcessingTvg = 4;      ///< time-varied gain applied
inline constexpr std::uint16_t kProcessingBacGac = 8;   ///< beam/grazing-angle corrections
inline constexpr std::uint16_t kProcessingFilter = 16;  ///< filtered

struct WriterOptions {
  SampleEncoding sample_encoding = SampleEncoding::kUint16;
  /// Accept more than kMaxPortableSamples samples per channel (MB-System then drops the pings).
  bool allow_more_than_8192_samples = false;
  /// SonarName in the file header, at most 16 characters.
  std::string sonar_name = "sonarsynth";
  /// Text of the NOTES packet written first (at most 200 characters); its first 64 characters
  /// also go to the file header's NoteString.
  std::string note = "synthetic side-scan data written by sonarsynth";
  double frequency_khz = 500.0;  ///< centre frequency, kHz, (0, 65535]
  /// Along-track beam width, [0, pi); 0 = not stated.
  double horizontal_beam_angle_rad = rad_from_deg(1.0);
  double tilt_angle_rad = rad_from_deg(30.0);  ///< depression of the beam axis below horizontal
  /// One-way -3 dB across-track (vertical) beam width, [0, pi); 0 = not stated.
  double vertical_beam_width_rad = rad_from_deg(50.0);
  /// XTFPINGCHANHEADER ProcessingFlags of every channel: a sum of kProcessingTvg,
  /// kProcessingBacGac, kProcessingFilter (docs/xtf.md §1.6); 0 = raw samples.
  std::uint16_t processing_flags = 0;
  bool overwrite = false;  ///< replace an existing file

  /// Throws InputError naming the violated constraint.
  void validate() const;
  /// One sentence per choice that some common reader does not accept, naming the readers.
  /// Empty for the default options.
  std::vector<std::string> compatibility_warnings() const;
};

/// A ping's header records as an earlier XTF file stored them (`convert` carries them through
/// JSF: docs/conversion.md, "Lossless round trip").
struct StoredPingHeaders {
  XtfPingHeader ping;
  std::array<XtfPingChanHeader, 2> channels{};  ///< port, starboard
};

/// Streaming XTF writer following the recommended profile of docs/xtf.md §5: NavUnits 3
/// (X = longitude, Y = latitude), channel 0 = port (stored far -> near), channel 1 = starboard,
/// SoundVelocity = c/2 and ComputedSoundVelocity = c, TimeDuration = SecondsPerPing =
/// SlantRange/SoundVelocity, every packet zero-padded to 64 bytes with NumBytesThisRecord = the
/// padded size, a NOTES packet first.
///
/// The file is written under a temporary name and appears under `path` only when close()
/// succeeds; destroying a Writer without close() leaves nothing behind. Memory use does not
/// grow with the number of pings; offsets are 64-bit, so files larger than 4 GB work.
class Writer : public SonarFileWriter {
 public:
  /// Throws InputError for invalid options, FormatError if the file cannot be created.
  explicit Writer(std::filesystem::path path, WriterOptions options = {});
  ~Writer();

  /// Appends one ping. Its time is stored rounded to the nearest 10 ms (XTF's HSeconds), with
  /// the carry into seconds, minutes, hours and the date. Throws InputError naming the field if
  /// the ping is invalid (no file position, altitude <= 0, bad time, wrong sample count...),
  /// FormatError on a write error.
  /// With `stored`, its records are written as they are (the position is not checked: a ping
  /// that had none keeps its zero coordinates) except the packet size, NumChansToFollow, the
  /// channel numbers and sample counts; only the samples are taken from `ping`.
  void write_ping(const SonarPing& ping, const StoredPingHeaders* stored = nullptr);
  /// Appends a 64-byte attitude packet (type 3).
  void write_attitude(const AttitudeSample& attitude);
  /// Appends a 64-byte navigation packet (type 42).
  void write_navigation(const NavigationFix& fix);
  /// Flushes, closes and renames the file into place. Throws FormatError on failure.
  void close();

  // clipped_samples(): samples that were rounded outside the encoding's range (or non-finite) and
  // clamped.
  /// options.compatibility_warnings(), for the caller to show.
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  void start(UtcTime first_time, std::uint32_t port_samples, std::uint32_t stbd_samples);
  void append(const std::vector<std::uint8_t>& bytes, std::size_t n);
  /// Encodes a fixed-size record (its kSize bytes) and appends it.
  template <class Record>
  void append_record(const Record& record) {
    buffer_.assign(Record::kSize, 0);
    ByteWriter w(buffer_);
    record.encode(w);
    append(buffer_, Record::kSize);
  }
  void encode_samples(const std::vector<float>& samples, bool reverse, ByteWriter& w);
  void validate_ping(const SonarPing& ping, bool check_position) const;

  WriterOptions options_;
  XtfFileHeader header_;
  bool header_needs_samples_ = true;   ///< CHANINFO.Reserved not yet set from a ping
  bool header_patch_pending_ = false;  ///< close() must rewrite the header
  std::ofstream out_;
  std::vector<char> stream_buffer_;
  std::vector<std::uint8_t> buffer_;
  std::vector<std::string> warnings_;
  bool started_ = false;
  bool closed_ = false;
};

/// The number of bytes a packet of `n` bytes occupies once padded to a multiple of 64.
constexpr std::uint64_t padded_size(std::uint64_t n) {
  return (n + kPacketAlignment - 1) / kPacketAlignment * kPacketAlignment;
}

}  // namespace sonarsynth::xtf
