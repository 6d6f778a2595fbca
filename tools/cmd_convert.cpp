// SPDX-License-Identifier: MIT
// `sonarsynth convert IN -o OUT`: between the formats of the format list that convert into
// each other (SonarFormat::conversions; today XTF <-> JSF, docs/jsf.md §4).
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "sonarsynth/formats/jsf/convert.hpp"
#include "sonarsynth/formats/products/output_paths.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"

namespace sonarsynth::cli {

int run_convert(const std::vector<std::string>& args) {
  po::options_description opts("options");
  std::string input, output, altitude_source = "header";
  // clang-format off
  opts.add_options()
    ("input", po::value(&input)->required(), "XTF, JSF or ROS 1 bag file (positional; format from content)")
    ("output,o", po::value(&output)->required(), "output file: .jsf, .xtf or .bag (format from extension)")
    ("altitude-source", po::value(&altitude_source)->default_value("header"),
     "header | auto | track: header copies the altitude; auto writes the altitude tracked from "
     "the first return where the header's is missing, <= 0 or disagrees; track everywhere "
     "(docs/conversion.md)");
  // clang-format on
  add_overwrite_quiet_options(opts);
  po::variables_map vm;
  if (!parse(
          args, opts, one_input(), vm,
          "usage: sonarsynth convert IN.xtf -o OUT.jsf | IN.jsf -o OUT.xtf | IN.xtf -o OUT.bag |\n"
          "                          IN.bag -o OUT.xtf | IN.bag -o OUT.jsf [options]\n\n"
          "Converts side-scan pings (port and starboard samples, time, navigation, attitude,\n"
          "altitude, depth, speed, sound speed, range) between XTF and JSF. Samples survive\n"
          "XTF -> JSF -> XTF bit-exactly; positions to JSF's 1/600 000 degree (docs/jsf.md).\n"
          "XTF -> ROS 1 bag and back: samples, time, position, attitude, sound speed\n"
          "(docs/rosbag.md); a bag of another source is read by its message types.")) {
    return 0;
  }
  refuse_output_over_input({output}, {input});
  const ConvertResult r =
      convert_sonar_file(input, output, vm.count("overwrite") > 0,
                         parse_altitude_source(altitude_source, "--altitude-source"));
  // Drops and repairs by reason (docs/conversion.md, "Drops and repairs"), then examples.
  if (r.pings_skipped > 0) {
    std::cerr << "sonarsynth convert: warning: dropped " << r.pings_skipped << " of "
              << r.pings + r.pings_skipped << " pings of " << input << ":\n";
    for (const auto& [reason, n] : r.dropped) std::cerr << "  " << reason << ": " << n << "\n";
  }
  if (!r.repaired.empty()) {
    std::cerr << "sonarsynth convert: warning: fields written as unknown (pings):\n";
    for (const auto& [rule, n] : r.repaired) std::cerr << "  " << rule << ": " << n << "\n";
  }
  if (r.pings_skipped > 0 || r.reader_anomalies > 0) {
    std::cerr << "sonarsynth convert: warning: " << r.reader_anomalies
              << " reader anomalies; first drops and anomalies:\n";
    for (const std::string& w : r.warnings) std::cerr << "  " << w << "\n";
  }
  if (!vm.count("quiet")) {
    std::cout << "wrote " << output << ": " << r.from->display_name << " -> " << r.to->display_name
              << ", " << r.pings << " pings, " << r.attitude_records << " attitude records";
    if (vm["altitude-source"].as<std::string>() != "header") {
      std::cout << ", altitude of " << r.pings_tracked_altitude
                << " pings tracked from the first return";
    }
    std::cout << "\n";
  }
  return 0;
}

}  // namespace sonarsynth::cli
