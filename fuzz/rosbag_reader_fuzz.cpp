// SPDX-License-Identifier: MIT
// libFuzzer target: the ROS 1 bag reader over arbitrary bytes must never crash, hang or allocate
// absurd memory. Structural damage throws FormatError (docs/rosbag.md, "Reading bags with
// sonarsynth"), from the constructor or from next_ping(); any other exception escaping is
// reported as a crash.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/rosbag/reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace rosbag = sonarsynth::rosbag;
  try {
    rosbag::Reader reader(std::span<const std::uint8_t>(data, size), "fuzz.bag");
    rosbag::Ping ping;
    while (reader.next_ping(ping)) {
    }
  } catch (const sonarsynth::FormatError&) {
    return 0;  // a clear error is an expected outcome
  }
  return 0;
}
