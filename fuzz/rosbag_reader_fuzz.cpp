// SPDX-License-Identifier: MIT
// libFuzzer target: the ROS 1 bag reader over arbitrary bytes must never crash, hang or allocate
// absurd memory. Structural damage throws FormatError (docs/rosbag.md, "Reading bags with
// sonarsynth"), from the constructor or from next_ping(); any other exception escaping is
// reported as a crash.
#include <cstddef>
#include <cstdint>

#include "bag_fuzz.hpp"
#include "sonarsynth/formats/rosbag/reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return read_every_ping<sonarsynth::rosbag::Reader>(data, size, "fuzz.bag");
}
