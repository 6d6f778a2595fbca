// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/sonar_format.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {

/// A rendered ping as an XTF ping: the local pose turned into WGS 84 (GeographicLib through the
/// scene's GeoFrame), grid heading into true heading (meridian convergence), samples as they are.
SonarPing to_xtf_ping(const RenderedPing& ping, const GeoFrame& frame, const SonarConfig& sonar);

/// The XTF sample encoding of a scene file's `output.sample_format`: "u16", "u8" or "f32".
/// Throws InputError naming the value otherwise.
xtf::SampleEncoding xtf_sample_encoding(const std::string& sample_format);

/// Every XTF header field that the simulation determines, derived here and nowhere else
/// (docs/xtf.md §1.2, §1.6, §5), from the configuration `sim` renders with:
/// - CHANINFO Frequency = sonar.frequency_hz in kHz; HorizBeamAngle = sonar.
///   horizontal_beam_width_rad; TiltAngle = sonar.tilt_rad; BeamWidth = the one-way -3 dB width
///   of sonar.vertical_beam (VerticalBeamPattern::width_3db_full_rad, 0 if it has none);
/// - ProcessingFlags = 4 (TVG) when output.tvg is not none, else 0;
/// - the note (NOTES packet, its first 64 characters the header's NoteString) starts with the
///   TVG law actually applied and the gain, in full, then the scene name (shortened if the note
///   would exceed 200 characters) and the seed;
/// - the sample encoding as given (`xtf_sample_encoding`); allow_more_than_8192_samples as given.
/// `overwrite` is left false.
xtf::WriterOptions xtf_writer_options(const Simulator& sim, xtf::SampleEncoding encoding,
                                      const std::string& scene_name,
                                      bool allow_more_than_8192_samples = false);

/// Writes one file per survey line (`<dir>/<line name><extension>`) through the format writer
/// `W` (constructed from a path and its `Options`), streaming: every ping goes through
/// to_xtf_ping, so that the files of every format of one run agree sample for sample. abort()
/// removes the file of the line being written (files of finished lines stay: the caller's
/// OutputDirectory discards them). XtfSurveyWriter and JsfSurveyWriter are its two formats.
template <class W, class Options>
class LineFileWriter : public SurveyFileSink {
 public:
  void begin_line(std::size_t line) override {
    const std::string name =
        line < names_.size() ? names_[line] : "line" + std::to_string(line + 1);
    writer_ = std::make_unique<W>(dir_ / (name + extension_), options_);
  }
  void ping(const RenderedPing& p) override {
    if (!writer_) throw Error(extension_ + " survey writer: ping outside a line");
    const SonarPing written = to_xtf_ping(p, frame_, sonar_);
    writer_->write_ping(written);
    after_ping(*writer_, written, p);
  }
  void end_line(std::size_t /*line*/) override {
    if (!writer_) return;
    writer_->close();
    clipped_ += writer_->clipped_samples();
    bytes_ += writer_->bytes_written();
    files_.push_back(writer_->path());
    writer_.reset();
  }
  void abort() noexcept override { writer_.reset(); }  // the writer removes its temporary file

  /// Files written so far (final paths).
  const std::vector<std::filesystem::path>& files() const override { return files_; }
  std::uint64_t clipped_samples() const { return clipped_; }
  std::uint64_t bytes_written() const { return bytes_; }

 protected:
  /// Called after each ping is written, with the ping as written and as rendered: a format
  /// that stores more of the rendered ping (the bags' truth topics) writes it here.
  virtual void after_ping(W& /*writer*/, const SonarPing& /*written*/,
                          const RenderedPing& /*rendered*/) {}
  /// `frame` and `sonar` are copied; `options` are validated here.
  LineFileWriter(std::filesystem::path dir, std::vector<std::string> line_names,
                 const GeoFrame& frame, const SonarConfig& sonar, Options options,
                 std::string extension)
      : dir_(std::move(dir)),
        names_(std::move(line_names)),
        frame_(frame),
        sonar_(sonar),
        options_(std::move(options)),
        extension_(std::move(extension)) {
    options_.validate();
  }

 private:
  std::filesystem::path dir_;
  std::vector<std::string> names_;
  GeoFrame frame_;
  SonarConfig sonar_;
  Options options_;
  std::string extension_;
  std::unique_ptr<W> writer_;
  std::vector<std::filesystem::path> files_;
  std::uint64_t clipped_ = 0, bytes_ = 0;
};

/// Writes one XTF file per survey line (`<dir>/<line name>.xtf`).
class XtfSurveyWriter : public LineFileWriter<xtf::Writer, xtf::WriterOptions> {
 public:
  /// `frame` and `sonar` are copied.
  XtfSurveyWriter(std::filesystem::path dir, std::vector<std::string> line_names,
                  const GeoFrame& frame, const SonarConfig& sonar, xtf::WriterOptions options)
      : LineFileWriter(std::move(dir), std::move(line_names), frame, sonar, std::move(options),
                       ".xtf") {}
};

}  // namespace sonarsynth
