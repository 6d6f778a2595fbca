// SPDX-License-Identifier: MIT
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sonarsynth/formats/xtf/writer.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {

/// A rendered ping as an XTF ping: the local pose turned into WGS 84 (GeographicLib through the
/// scene's GeoFrame), grid heading into true heading (meridian convergence), samples as they are.
xtf::SonarPing to_xtf_ping(const RenderedPing& ping, const GeoFrame& frame,
                           const SonarConfig& sonar);

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

/// Writes one XTF file per survey line (`<dir>/<line name>.xtf`), streaming. Extra sinks (mosaic,
/// waterfall, truth) can be chained: every ping is passed on to them. abort() removes the file of
/// the line being written (files of finished lines stay: the caller's OutputDirectory discards
/// them).
class XtfSurveyWriter : public PingSink {
 public:
  /// `frame` and `sonar` are copied.
  XtfSurveyWriter(std::filesystem::path dir, std::vector<std::string> line_names,
                  const GeoFrame& frame, const SonarConfig& sonar, xtf::WriterOptions options);
  void begin_line(std::size_t line) override;
  void ping(const RenderedPing& ping) override;
  void end_line(std::size_t line) override;
  void abort() noexcept override;

  /// Files written so far (final paths).
  const std::vector<std::filesystem::path>& files() const { return files_; }
  std::uint64_t clipped_samples() const { return clipped_; }
  std::uint64_t bytes_written() const { return bytes_; }

 private:
  std::filesystem::path dir_;
  std::vector<std::string> names_;
  GeoFrame frame_;
  SonarConfig sonar_;
  xtf::WriterOptions options_;
  std::unique_ptr<xtf::Writer> writer_;
  std::vector<std::filesystem::path> files_;
  std::uint64_t clipped_ = 0, bytes_ = 0;
};

/// Passes every call on to several sinks, in order. The sinks are borrowed: they must outlive
/// the TeeSink's use (as locals declared before it).
class TeeSink : public PingSink {
 public:
  explicit TeeSink(std::vector<PingSink*> sinks) : sinks_(std::move(sinks)) {}
  void begin(const RunDescription& run) override {
    for (auto* s : sinks_) s->begin(run);
  }
  void begin_line(std::size_t line) override {
    for (auto* s : sinks_) s->begin_line(line);
  }
  void ping(const RenderedPing& p) override {
    for (auto* s : sinks_) s->ping(p);
  }
  void end_line(std::size_t line) override {
    for (auto* s : sinks_) s->end_line(line);
  }
  void finish() override {
    for (auto* s : sinks_) s->finish();
  }
  void abort() noexcept override {
    for (auto* s : sinks_) s->abort();
  }

 private:
  std::vector<PingSink*> sinks_;
};

}  // namespace sonarsynth
