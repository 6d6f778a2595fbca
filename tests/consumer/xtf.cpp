// SPDX-License-Identifier: MIT
// Component xtf: writes a small XTF file and reads it back. Also the program of the xtf-only
// downstream project (xtf/CMakeLists.txt), which finds neither GDAL nor yaml-cpp.
#include <filesystem>
#include <iostream>

#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/summary.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"

int main() {
  namespace xtf = sonarsynth::xtf;
  const auto path = std::filesystem::temp_directory_path() / "sonarsynth_consumer_xtf.xtf";
  {
    xtf::WriterOptions options;
    options.overwrite = true;
    xtf::Writer writer(path, options);
    for (std::uint32_t i = 0; i < 3; ++i) {
      sonarsynth::SonarPing ping;
      ping.time_utc = sonarsynth::UtcTime(std::chrono::seconds(1'700'000'000 + i));
      ping.ping_number = i;
      ping.sensor_position = {sonarsynth::rad_from_deg(48.45), sonarsynth::rad_from_deg(-68.83)};
      ping.altitude_m = 10.0;
      ping.slant_range_m = 50.0;
      ping.port.assign(64, 100.0f);
      ping.starboard.assign(64, 200.0f);
      writer.write_ping(ping);
    }
    writer.close();
  }
  const xtf::FileSummary summary = xtf::summarize_file(path);
  std::filesystem::remove(path);
  std::cout << "xtf: " << summary.pings << " pings read back\n";
  return summary.pings == 3 ? 0 : 1;
}
