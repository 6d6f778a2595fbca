// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/jsf/survey_writer.hpp"

namespace sonarsynth {
namespace {

jsf::WriterOptions with_sonar_frequency(jsf::WriterOptions options, const SonarConfig& sonar) {
  if (sonar.frequency_hz > 0.0 && sonar.frequency_hz <= 655350.0) {
    options.frequency_hz = sonar.frequency_hz;
  }
  return options;
}

}  // namespace

JsfSurveyWriter::JsfSurveyWriter(std::filesystem::path dir, std::vector<std::string> line_names,
                                 const GeoFrame& frame, const SonarConfig& sonar,
                                 jsf::WriterOptions options)
    : LineFileWriter(std::move(dir), std::move(line_names), frame, sonar,
                     with_sonar_frequency(std::move(options), sonar), ".jsf") {}

}  // namespace sonarsynth
