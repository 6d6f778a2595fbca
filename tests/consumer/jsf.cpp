// SPDX-License-Identifier: MIT
// Component jsf: writes a small JSF file, reads it back and converts it to XTF. Also the program
// of the jsf-only downstream project (jsf/CMakeLists.txt), which finds neither GDAL nor yaml-cpp.
#include <filesystem>
#include <iostream>

#include "sonarsynth/formats/jsf/convert.hpp"
#include "sonarsynth/formats/jsf/summary.hpp"
#include "sonarsynth/formats/jsf/writer.hpp"
#include "test_pings.hpp"

int main() {
  namespace jsf = sonarsynth::jsf;
  const auto dir = std::filesystem::temp_directory_path();
  const auto path = dir / "sonarsynth_consumer_jsf.jsf";
  const auto xtf_path = dir / "sonarsynth_consumer_jsf.xtf";
  {
    jsf::WriterOptions options;
    options.overwrite = true;
    jsf::Writer writer(path, options);
    write_test_pings(writer, 3, 48.0);
  }
  const jsf::FileSummary summary = jsf::summarize_file(path);
  const sonarsynth::ConvertResult converted =
      sonarsynth::jsf_to_xtf(path, xtf_path, true, sonarsynth::AltitudeSource::kHeader);
  std::filesystem::remove(path);
  std::filesystem::remove(xtf_path);
  std::cout << "jsf: " << summary.pings << " pings read back, " << converted.pings
            << " converted to XTF\n";
  return summary.pings == 3 && converted.pings == 3 ? 0 : 1;
}
