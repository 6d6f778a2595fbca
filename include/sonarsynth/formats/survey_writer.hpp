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

/// Writes one XTF file per survey line (`<dir>/<line name>.xtf`), streaming. Extra sinks (mosaic,
/// waterfall, truth) can be chained: every ping is passed on to them.
class XtfSurveyWriter : public PingSink {
 public:
  XtfSurveyWriter(std::filesystem::path dir, std::vector<std::string> line_names,
                  const GeoFrame& frame, const SonarConfig& sonar, xtf::WriterOptions options);
  void begin_line(std::size_t line) override;
  void ping(const RenderedPing& ping) override;
  void end_line(std::size_t line) override;

  /// Files written so far (final paths).
  const std::vector<std::filesystem::path>& files() const { return files_; }
  std::uint64_t clipped_samples() const { return clipped_; }
  std::uint64_t bytes_written() const { return bytes_; }

 private:
  std::filesystem::path dir_;
  std::vector<std::string> names_;
  const GeoFrame& frame_;
  SonarConfig sonar_;
  xtf::WriterOptions options_;
  std::unique_ptr<xtf::Writer> writer_;
  std::vector<std::filesystem::path> files_;
  std::uint64_t clipped_ = 0, bytes_ = 0;
};

/// Passes every call on to several sinks, in order.
class TeeSink : public PingSink {
 public:
  explicit TeeSink(std::vector<PingSink*> sinks) : sinks_(std::move(sinks)) {}
  void begin_line(std::size_t line) override {
    for (auto* s : sinks_) s->begin_line(line);
  }
  void ping(const RenderedPing& p) override {
    for (auto* s : sinks_) s->ping(p);
  }
  void end_line(std::size_t line) override {
    for (auto* s : sinks_) s->end_line(line);
  }

 private:
  std::vector<PingSink*> sinks_;
};

}  // namespace sonarsynth
