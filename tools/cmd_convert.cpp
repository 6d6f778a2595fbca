// SPDX-License-Identifier: MIT
// `sonarsynth convert IN -o OUT`: between the formats of the format list that convert into
// each other (SonarFormat::conversions, docs/conversion.md). The help lists what the format list
// offers, so a new format's conversions appear without a line here.
#include <algorithm>
#include <iostream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "sonarsynth/formats/jsf/convert.hpp"
#include "sonarsynth/formats/products/output_paths.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"

namespace sonarsynth::cli {
namespace {

// "  IN.xtf -o OUT.jsf    XTF -> JSF" per conversion of the format list (once each), the
// descriptions in one column.
std::string conversion_lines() {
  std::set<std::pair<std::string_view, std::string_view>> seen;
  std::vector<std::pair<std::string, std::string>> rows;  // command, description
  std::size_t width = 0;
  for (const SonarFormat* f : sonar_formats()) {
    for (const SonarConversion& c : f->conversions) {
      if (!seen.insert({c.from, c.to}).second) continue;
      const SonarFormat* from = find_sonar_format(c.from);
      const SonarFormat* to = find_sonar_format(c.to);
      if (!from || !to) continue;
      rows.emplace_back("IN" + std::string(from->extensions.front()) + " -o OUT" +
                            std::string(to->extensions.front()),
                        std::string(from->display_name) + " -> " + std::string(to->display_name));
      width = std::max(width, rows.back().first.size());
    }
  }
  std::string out;
  for (const auto& [command, description] : rows) {
    out += "  " + command + std::string(width - command.size() + 3, ' ') + description + "\n";
  }
  if (!out.empty()) out.pop_back();  // the usage text ends without a newline
  return out;
}

// "XTF, JSF or ROS 1 bag" of the formats `pick` selects.
template <typename Pick>
std::string format_list(Pick pick, bool extensions) {
  std::vector<std::string> names;
  for (const SonarFormat* f : sonar_formats()) {
    if (pick(*f)) names.emplace_back(extensions ? f->extensions.front() : f->display_name);
  }
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  }
  return out;
}

}  // namespace

int run_convert(const std::vector<std::string>& args) {
  po::options_description opts("options");
  std::string input, output, altitude_source = "header";
  const auto readable = [](const SonarFormat& f) { return f.capabilities.read; };
  const auto target = [](const SonarFormat& f) {
    for (const SonarFormat* g : sonar_formats()) {
      for (const SonarConversion& c : g->conversions) {
        if (c.to == f.name) return true;
      }
    }
    return false;
  };
  const std::string input_help =
      format_list(readable, false) + " file (positional; format from content)";
  const std::string output_help =
      "output file: " + format_list(target, true) + " (format from extension)";
  // clang-format off
  opts.add_options()
    ("input", po::value(&input)->required(), input_help.c_str())
    ("output,o", po::value(&output)->required(), output_help.c_str())
    ("altitude-source", po::value(&altitude_source)->default_value("header"),
     "header | auto | track: header copies the altitude; auto writes the altitude tracked from "
     "the first return where the header's is missing, <= 0 or disagrees; track everywhere "
     "(docs/conversion.md)");
  // clang-format on
  add_overwrite_quiet_options(opts);
  po::variables_map vm;
  if (!parse(args, opts, one_input(), vm,
             "usage: sonarsynth convert IN -o OUT [options]\n\n"
             "Converts side-scan pings (port and starboard samples, time, navigation, attitude,\n"
             "altitude, depth, speed, sound speed, range) between sonar formats: the input's\n"
             "format from its content, the output's from its extension (docs/conversion.md).\n"
             "Conversions:\n" +
                 conversion_lines())) {
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
