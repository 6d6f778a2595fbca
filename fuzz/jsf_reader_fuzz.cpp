// SPDX-License-Identifier: MIT
// libFuzzer target: the JSF reader over arbitrary bytes must never crash, hang or allocate
// absurd memory. Only the constructor may throw (FormatError: not a JSF file); once a file is
// open, every broken message must become an anomaly and reading messages, assembling pings and
// summarising never throw: an exception escaping from there is reported as a crash.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/jsf/reader.hpp"
#include "sonarsynth/formats/jsf/summary.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace jsf = sonarsynth::jsf;
  jsf::ReaderOptions options;
  options.max_message_bytes = std::uint64_t{16} << 20;
  options.max_anomaly_messages = 64;
  const std::span<const std::uint8_t> bytes(data, size);
  std::optional<jsf::Reader> reader;
  try {
    reader.emplace(bytes, "fuzz.jsf", options);
  } catch (const sonarsynth::FormatError&) {
    return 0;  // not a JSF file: a clear error is the expected outcome
  }
  const jsf::FileSummary s = jsf::summarize(*reader);
  if (s.first_time) (void)sonarsynth::xtf::iso8601(*s.first_time);
  jsf::Reader messages(bytes, "fuzz.jsf", options);
  jsf::Message m;
  while (messages.next(m)) {
  }
  return 0;
}
