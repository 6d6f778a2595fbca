// SPDX-License-Identifier: MIT
// What the fuzz targets of the ROS bag readers (ROS 1 bag, MCAP) share: every ping of the bytes
// read, a FormatError (structural damage, from the constructor or from next_ping()) being an
// expected outcome; any other exception escaping is reported as a crash.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/rosbag/reader.hpp"

template <class BagReader>
int read_every_ping(const std::uint8_t* data, std::size_t size, const char* name) {
  try {
    BagReader reader(std::span<const std::uint8_t>(data, size), name);
    sonarsynth::rosbag::Ping ping;
    while (reader.next_ping(ping)) {
    }
  } catch (const sonarsynth::FormatError&) {
    return 0;  // a clear error is an expected outcome
  }
  return 0;
}
