// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "sonarsynth/formats/jsf/writer.hpp"
#include "sonarsynth/formats/xtf/survey_writer.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth {

/// Writes one JSF file per survey line (`<dir>/<line name>.jsf`), streaming: the same pings as
/// XtfSurveyWriter (to_xtf_ping), so that the JSF and XTF of one run agree sample for sample.
/// abort() removes the file of the line being written.
class JsfSurveyWriter : public LineFileWriter<jsf::Writer, jsf::WriterOptions> {
 public:
  /// `frame` and `sonar` are copied; options.frequency_hz is set from sonar.frequency_hz when
  /// the JSF field can hold it.
  JsfSurveyWriter(std::filesystem::path dir, std::vector<std::string> line_names,
                  const GeoFrame& frame, const SonarConfig& sonar, jsf::WriterOptions options);
};

}  // namespace sonarsynth
