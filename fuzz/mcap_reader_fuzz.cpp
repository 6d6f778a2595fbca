// SPDX-License-Identifier: MIT
// libFuzzer target: the MCAP reader over arbitrary bytes must never crash, hang or allocate
// absurd memory. Structural damage throws FormatError (docs/robotics.md, "Reading bags"), from
// the constructor or from next_ping(); any other exception escaping is reported as a crash.
#include <cstddef>
#include <cstdint>
#include <span>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/mcap/reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace mcap = sonarsynth::mcap;
  try {
    mcap::Reader reader(std::span<const std::uint8_t>(data, size), "fuzz.mcap");
    mcap::Ping ping;
    while (reader.next_ping(ping)) {
    }
  } catch (const sonarsynth::FormatError&) {
    return 0;  // a clear error is an expected outcome
  }
  return 0;
}
