// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "sonarsynth/formats/jsf/writer.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {

/// Writes one JSF file per survey line (`<dir>/<line name>.jsf`), streaming: the same pings as
/// XtfSurveyWriter (to_xtf_ping), so that the JSF and XTF of one run agree sample for sample.
/// abort() removes the file of the line being written.
class JsfSurveyWriter : public PingSink {
 public:
  /// `frame` and `sonar` are copied; options.frequency_hz is set from sonar.frequency_hz.
  JsfSurveyWriter(std::filesystem::path dir, std::vector<std::string> line_names,
                  const GeoFrame& frame, const SonarConfig& sonar, jsf::WriterOptions options);
  void begin_line(std::size_t line) override;
  void ping(const RenderedPing& ping) override;
  void end_line(std::size_t line) override;
  void abort() noexcept override;

  const std::vector<std::filesystem::path>& files() const { return files_; }
  std::uint64_t clipped_samples() const { return clipped_; }
  std::uint64_t bytes_written() const { return bytes_; }

 private:
  std::filesystem::path dir_;
  std::vector<std::string> names_;
  GeoFrame frame_;
  SonarConfig sonar_;
  jsf::WriterOptions options_;
  std::unique_ptr<jsf::Writer> writer_;
  std::vector<std::filesystem::path> files_;
  std::uint64_t clipped_ = 0, bytes_ = 0;
};

}  // namespace sonarsynth
