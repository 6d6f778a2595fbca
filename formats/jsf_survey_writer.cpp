// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/jsf_survey_writer.hpp"

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/survey_writer.hpp"

namespace sonarsynth {

JsfSurveyWriter::JsfSurveyWriter(std::filesystem::path dir, std::vector<std::string> line_names,
                                 const GeoFrame& frame, const SonarConfig& sonar,
                                 jsf::WriterOptions options)
    : dir_(std::move(dir)),
      names_(std::move(line_names)),
      frame_(frame),
      sonar_(sonar),
      options_(std::move(options)) {
  if (sonar_.frequency_hz > 0.0 && sonar_.frequency_hz <= 655350.0) {
    options_.frequency_hz = sonar_.frequency_hz;
  }
  options_.validate();
}

void JsfSurveyWriter::begin_line(std::size_t line) {
  const std::string name = line < names_.size() ? names_[line] : "line" + std::to_string(line + 1);
  writer_ = std::make_unique<jsf::Writer>(dir_ / (name + ".jsf"), options_);
}

void JsfSurveyWriter::ping(const RenderedPing& p) {
  if (!writer_) throw Error("jsf survey writer: ping outside a line");
  writer_->write_ping(to_xtf_ping(p, frame_, sonar_));
}

void JsfSurveyWriter::abort() noexcept {
  writer_.reset();  // the Writer removes its temporary file
}

void JsfSurveyWriter::end_line(std::size_t /*line*/) {
  if (!writer_) return;
  writer_->close();
  clipped_ += writer_->clipped_samples();
  bytes_ += writer_->bytes_written();
  files_.push_back(writer_->path());
  writer_.reset();
}

}  // namespace sonarsynth
