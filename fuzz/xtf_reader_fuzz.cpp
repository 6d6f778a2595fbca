// SPDX-License-Identifier: MIT
// libFuzzer target: the XTF reader over arbitrary bytes must never crash, hang or allocate
// absurd memory. Only the constructor may throw (FormatError: not an XTF file); once a file is
// open, every broken packet must become an anomaly and reading and summarising never throw:
// an exception escaping from there aborts the run and is reported as a crash.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/summary.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace xtf = sonarsynth::xtf;
  xtf::ReaderOptions options;
  options.max_packet_bytes = std::uint64_t{16} << 20;
  options.max_anomaly_messages = 64;
  std::optional<xtf::Reader> reader;
  try {
    reader.emplace(std::span<const std::uint8_t>(data, size), "fuzz.xtf", options);
  } catch (const sonarsynth::FormatError&) {
    return 0;  // not an XTF file: a clear error is the expected outcome
  }
  const xtf::FileSummary s = xtf::summarize(*reader);
  if (s.first_time) (void)xtf::iso8601(*s.first_time);
  if (s.last_time) (void)xtf::iso8601(*s.last_time);
  return 0;
}
