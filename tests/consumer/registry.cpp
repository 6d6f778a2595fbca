// SPDX-License-Identifier: MIT
// Component registry: the format list, and a file written by one codec identified and read back
// through it (no GDAL, no yaml-cpp).
#include <filesystem>
#include <iostream>

#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"

int main() {
  const auto path = std::filesystem::temp_directory_path() / "sonarsynth_consumer_registry.xtf";
  {
    sonarsynth::xtf::WriterOptions options;
    options.overwrite = true;
    sonarsynth::xtf::Writer writer(path, options);
    sonarsynth::SonarPing ping;
    ping.time_utc = sonarsynth::UtcTime(std::chrono::seconds(1'700'000'000));
    ping.sensor_position = {sonarsynth::rad_from_deg(48.45), sonarsynth::rad_from_deg(-68.83)};
    ping.altitude_m = 10.0;
    ping.slant_range_m = 48.0;
    ping.port.assign(64, 100.0f);
    ping.starboard.assign(64, 200.0f);
    writer.write_ping(ping);
    writer.close();
  }
  const sonarsynth::SonarFormat* format = sonarsynth::identify_sonar_format(path);
  std::uint64_t pings = 0;
  sonarsynth::SideScanRecord record;
  for (auto source = sonarsynth::SideScanSource::open(path); source->next(record);) ++pings;
  std::filesystem::remove(path);
  std::cout << "registry: formats " << sonarsynth::sonar_format_names() << "; "
            << (format ? format->display_name : "none") << ", " << pings << " ping read back\n";
  return format && format->name == "xtf" && pings == 1 ? 0 : 1;
}
