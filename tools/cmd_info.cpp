// SPDX-License-Identifier: MIT
// `sonarsynth info FILE [--json]`: what is in a sonar file of any known format, like gdalinfo;
// the summary is the library's (sonar_file_info).
#include <iostream>
#include <string>

#include "commands.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"

namespace sonarsynth::cli {

int run_info(const std::vector<std::string>& args) {
  po::options_description options("Options");
  std::string input;
  std::size_t max_anomalies = 20;
  options.add_options()(
      "input,i", po::value<std::string>(&input)->required(),
      ("sonar file: " + sonar_format_names() + " (format from the content)").c_str())(
      "json", "print JSON instead of text")(
      "max-anomalies", po::value<std::size_t>(&max_anomalies)->default_value(20),
      "anomaly messages listed in the text output");
  po::variables_map vm;
  if (!parse(args, options, one_input(), vm,
             "usage: sonarsynth info FILE [--json]\n"
             "Reports a sonar file's (" +
                 sonar_format_names() +
                 ") header, channels or "
                 "subsystems, packet or message counts, pings, time span, navigation "
                 "extent, attitude ranges and anomalies.")) {
    return 0;
  }
  // The summary is the file format's (SonarFormat::info, formats/<codec>/info.cpp).
  const SonarFileInfo info = sonar_file_info(input, max_anomalies);
  if (vm.count("json")) {
    std::cout << info.json << "\n";
  } else {
    std::cout << info.text;
  }
  return 0;
}

}  // namespace sonarsynth::cli
