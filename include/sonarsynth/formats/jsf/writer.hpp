// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <vector>

#include "sonarsynth/formats/io/atomic_file.hpp"
#include "sonarsynth/formats/io/sonar_ping.hpp"
#include "sonarsynth/formats/jsf/records.hpp"

namespace sonarsynth::jsf {

/// Samples per channel this writer accepts (20 bits: offset 114 plus the MSB1 nibble).
inline constexpr std::size_t kMaxSamples = (std::size_t{1} << 20) - 1;

struct WriterOptions {
  /// Centre frequency, Hz, (0, 655 350]: mixer frequency and the (CW) pulse start/end frequency.
  double frequency_hz = 500e3;
  /// Subsystem of the side-scan messages: 20 (low or only frequency), 21 or 22.
  std::uint8_t subsystem = kSubsystemSideScanLow;
  /// System type of the system information message (182); 0 = not an EdgeTech system.
  std::int32_t system_type = 0;
  bool overwrite = false;  ///< replace an existing file
  /// XTF fields carried by a conversion: vendor bytes of the 182 message (docs/jsf.md §1.4).
  std::optional<XtfFileFields> xtf_file_fields;
  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// The weighting factor N (value = stored x 2^-N) and the stored int16 values of one channel
/// (docs/jsf.md §2.3): N = 0 when every sample is an integer in 0..32767 (stored exactly, and
/// PINGVerter, which ignores N, reads the same values); otherwise the largest N in [-200, 200]
/// with max * 2^N <= 32767. Negative and non-finite samples are stored as 0 and counted in
/// `clipped`.
std::int16_t quantise(std::span<const float> samples, std::vector<std::int16_t>& stored,
                      std::uint64_t& clipped);

/// The message-80 header (without the per-channel fields samples/channel/N/max) of `ping` as
/// this writer fills it: times, position (units 2, rounded to 1/600 000 degree), attitude,
/// altitude, depth, speed, sound speed, sample interval (round(2 R / (c n)) ns) and validity.
SonarDataHeader sonar_header(const SonarPing& ping, const WriterOptions& options);

/// Streaming JSF writer (docs/jsf.md §2): a system information message (182) first, then per
/// ping two sonar data messages (80) of subsystem `options.subsystem`, port (channel 0) then
/// starboard (channel 1), both near -> far, protocol version 13, byte count 240 + 2 n.
/// Attitude samples become pitch/roll messages (2020). The file is written under a temporary
/// name and appears under `path` only when close() succeeds.
class Writer : public SonarFileWriter {
 public:
  /// Throws InputError for invalid options, FormatError if the file cannot be created.
  explicit Writer(std::filesystem::path path, WriterOptions options = {});
  ~Writer();

  /// Appends one ping (two messages). Throws InputError naming the field if the ping cannot be
  /// stored (no position, time before 1970 or after 2100, empty side, too many samples...).
  /// A NaN heading, speed, pitch, roll, heave, depth or sound speed is "unknown": written as 0
  /// (sound speed: kAssumedSoundSpeed_m_s, which sets the sample interval) with its validity
  /// bit clear; an altitude of 0 clears the altitude bit.
  /// `xtf_fields` (a conversion's): written as a message 9999 right before the ping's port
  /// message (docs/jsf.md §1.4).
  void write_ping(const SonarPing& ping, const XtfPingFields* xtf_fields = nullptr);
  /// Appends a 44-byte pitch/roll message (2020) with pitch, roll, heave, heading and yaw.
  void write_attitude(const AttitudeSample& attitude);
  /// Flushes, closes and renames the file into place. Throws FormatError on failure.
  void close();

  // clipped_samples(): samples that were negative or non-finite and stored as 0.

 private:
  void start();
  void append(std::size_t n);
  void write_channel(const SonarDataHeader& base, std::uint8_t channel,
                     const std::vector<float>& samples);

  WriterOptions options_;
  std::ofstream out_;
  std::vector<char> stream_buffer_;
  std::vector<std::uint8_t> buffer_;
  std::vector<std::int16_t> stored_;
  bool started_ = false;
  bool closed_ = false;
};

}  // namespace sonarsynth::jsf
