// SPDX-License-Identifier: MIT
// Component registry: the format list, and a file written by one codec identified and read back
// through it (no GDAL, no yaml-cpp).
#include <filesystem>
#include <iostream>

#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "test_pings.hpp"

int main() {
  const auto path = std::filesystem::temp_directory_path() / "sonarsynth_consumer_registry.xtf";
  {
    sonarsynth::xtf::WriterOptions options;
    options.overwrite = true;
    sonarsynth::xtf::Writer writer(path, options);
    write_test_pings(writer, 1, 48.0);
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
