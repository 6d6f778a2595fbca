// SPDX-License-Identifier: MIT
// The XTF format's descriptor (docs/xtf.md, docs/architecture.md "Adding a sonar format").
#include "sonarsynth/formats/xtf/format.hpp"

#include <memory>
#include <string>
#include <vector>

#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/records.hpp"
#include "sonarsynth/formats/xtf/survey_writer.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"

namespace sonarsynth::xtf {
namespace {

class XtfSource : public ReaderSource<Reader> {
 public:
  explicit XtfSource(const std::filesystem::path& path) : ReaderSource(path, sonar_format()) {}
  bool next(SideScanRecord& r) override {
    while (reader_.next(packet_)) {
      if (packet_.kind != PacketKind::kPing) continue;
      r.sonar = std::move(packet_.ping.sonar);
      r.nav_valid = packet_.ping.nav_valid && reader_.file_header().NavUnits == 3;
      r.time_valid = packet_.ping.time_valid;
      r.layback_m = packet_.ping.header.Layback;
      r.heading_true_deg = packet_.ping.header.SensorHeading;
      r.index = packet_.index;
      return true;
    }
    return false;
  }

 private:
  Packet packet_;
};

/// XtfSurveyWriter with the header settings' compatibility warnings.
class XtfSurveySink : public XtfSurveyWriter {
 public:
  XtfSurveySink(const SurveyWriterContext& c, WriterOptions o)
      : XtfSurveyWriter(c.dir, c.line_names, *c.frame, *c.sonar, o),
        warnings_(o.compatibility_warnings()) {}
  std::vector<std::string> compatibility_warnings() const override { return warnings_; }

 private:
  std::vector<std::string> warnings_;
};

bool identify(std::span<const std::uint8_t> head) {
  return !head.empty() && head[0] == kFileFormat;
}

std::unique_ptr<SideScanSource> open_reader(const std::filesystem::path& path) {
  return std::make_unique<XtfSource>(path);
}

std::unique_ptr<SurveyFileSink> create_survey_writer(const SurveyWriterContext& c) {
  WriterOptions o = xtf_writer_options(*c.simulator, xtf_sample_encoding(c.sample_format),
                                       c.scene_name, c.allow_more_than_8192_samples);
  o.overwrite = true;  // inside the run's own fresh temporary directory
  return std::make_unique<XtfSurveySink>(c, std::move(o));
}

// Each ping: the ping header and two channel headers with their samples, padded (docs/xtf.md);
// each file: the 1024-byte file header and the notes packet, rounded up.
double estimated_bytes(const SonarConfig& sonar, const std::string& sample_format, double pings,
                       std::size_t lines) {
  const std::size_t bytes_per_sample = sample_format == "u8" ? 1 : sample_format == "f32" ? 4 : 2;
  const double ping = static_cast<double>(
      padded_size(XtfPingHeader::kSize + 2 * (64 + sonar.samples_per_channel * bytes_per_sample)));
  return pings * ping + 2048.0 * static_cast<double>(lines);
}

}  // namespace

const SonarFormat& sonar_format() {
  static const SonarFormat format = reading_and_simulating_format(
      "xtf", "XTF", "eXtended Triton Format (Triton Imaging)", {".xtf"}, identify, open_reader,
      file_info, create_survey_writer, estimated_bytes, {});
  return format;
}

}  // namespace sonarsynth::xtf
