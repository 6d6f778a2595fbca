// SPDX-License-Identifier: MIT
// libFuzzer target: the XTF reader over arbitrary bytes must never crash, hang or allocate
// absurd memory; FormatError for a bad file header is the only exception allowed.
#include <cstddef>
#include <cstdint>
#include <span>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/summary.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace xtf = sonarsynth::xtf;
  try {
    xtf::ReaderOptions options;
    options.max_packet_bytes = std::uint64_t{16} << 20;
    options.max_anomaly_messages = 64;
    xtf::Reader reader(std::span<const std::uint8_t>(data, size), "fuzz", options);
    const xtf::FileSummary s = xtf::summarize(reader);
    (void)s;
  } catch (const sonarsynth::FormatError&) {
    // not an XTF file: a clear error is the expected outcome
  }
  return 0;
}
