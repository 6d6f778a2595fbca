// SPDX-License-Identifier: MIT
// Component xtf: writes a small XTF file and reads it back. Also the program of the xtf-only
// downstream project (xtf/CMakeLists.txt), which finds neither GDAL nor yaml-cpp.
#include <filesystem>
#include <iostream>

#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/summary.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "test_pings.hpp"

int main() {
  namespace xtf = sonarsynth::xtf;
  const auto path = std::filesystem::temp_directory_path() / "sonarsynth_consumer_xtf.xtf";
  {
    xtf::WriterOptions options;
    options.overwrite = true;
    xtf::Writer writer(path, options);
    write_test_pings(writer, 3, 50.0);
  }
  const xtf::FileSummary summary = xtf::summarize_file(path);
  std::filesystem::remove(path);
  std::cout << "xtf: " << summary.pings << " pings read back\n";
  return summary.pings == 3 ? 0 : 1;
}
