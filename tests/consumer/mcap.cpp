// SPDX-License-Identifier: MIT
// Component mcap: writes a small ROS 2 bag (docs/robotics.md), checks its magic bytes and reads
// its pings back with the component's reader. Also the program of the mcap-only downstream
// project, which finds neither GDAL nor yaml-cpp.
#include <array>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "sonarsynth/formats/mcap/reader.hpp"
#include "sonarsynth/formats/mcap/writer.hpp"
#include "test_pings.hpp"

int main() {
  namespace mcap = sonarsynth::mcap;
  const auto [path, messages] = write_test_file<mcap::Writer, mcap::WriterOptions>(
      "sonarsynth_consumer_mcap.mcap", &mcap::Writer::messages_written);
  std::array<char, 8> head{}, tail{};
  std::ifstream f(path, std::ios::binary);
  f.read(head.data(), 8);
  f.seekg(-8, std::ios::end);
  f.read(tail.data(), 8);
  f.close();
  std::size_t pings = 0;
  {
    mcap::Reader reader(path);
    mcap::Ping ping;
    while (reader.next_ping(ping)) pings += ping.sonar.port.size() == 64 ? 1u : 0u;
  }
  std::filesystem::remove(path);
  const std::array<char, 8> magic = {'\x89', 'M', 'C', 'A', 'P', '0', '\r', '\n'};
  std::cout << "mcap: " << messages << " messages written, " << pings << " pings read\n";
  return messages == 13 && pings == 3 && head == magic && tail == magic ? 0 : 1;
}
