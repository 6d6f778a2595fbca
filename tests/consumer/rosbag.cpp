// SPDX-License-Identifier: MIT
// Component rosbag: writes a small ROS 1 bag and checks its "#ROSBAG V2.0" line, its size and the
// ping count (the rosbag-only downstream project finds neither GDAL nor yaml-cpp).
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "sonarsynth/formats/rosbag/writer.hpp"
#include "test_pings.hpp"

int main() {
  namespace rosbag = sonarsynth::rosbag;
  const auto [path, pings] = write_test_file<rosbag::Writer, rosbag::WriterOptions>(
      "sonarsynth_consumer_rosbag.bag", &rosbag::Writer::pings_written);
  std::string line;
  std::getline(std::ifstream(path, std::ios::binary), line);
  const auto bytes = std::filesystem::file_size(path);
  std::filesystem::remove(path);
  std::cout << "rosbag: " << pings << " pings, " << bytes << " bytes, \"" << line << "\"\n";
  // 3 pings x 2 sides x 64 u16 samples at least, after the 4096-byte bag header record.
  return pings == 3 && line == "#ROSBAG V2.0" && bytes > 4096 + 3 * 2 * 64 * 2 ? 0 : 1;
}
