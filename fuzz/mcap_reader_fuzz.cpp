// SPDX-License-Identifier: MIT
// libFuzzer target: the MCAP reader over arbitrary bytes must never crash, hang or allocate
// absurd memory. Structural damage throws FormatError (docs/robotics.md, "Reading bags"), from
// the constructor or from next_ping(); any other exception escaping is reported as a crash.
#include <cstddef>
#include <cstdint>

#include "bag_fuzz.hpp"
#include "sonarsynth/formats/mcap/reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return read_every_ping<sonarsynth::mcap::Reader>(data, size, "fuzz.mcap");
}
