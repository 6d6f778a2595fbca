// SPDX-License-Identifier: MIT
// The JSF format's descriptor (docs/jsf.md, docs/architecture.md "Adding a sonar format").
#include "sonarsynth/formats/jsf/format.hpp"

#include <memory>
#include <string>
#include <vector>

#include "sonarsynth/formats/jsf/convert.hpp"
#include "sonarsynth/formats/jsf/reader.hpp"
#include "sonarsynth/formats/jsf/records.hpp"
#include "sonarsynth/formats/jsf/survey_writer.hpp"
#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::jsf {
namespace {

/// Every JSF message starts with the marker bytes 01 16 (docs/jsf.md).
bool identify(std::span<const std::uint8_t> head) {
  return head.size() >= 2 && head[0] == (kStartMarker & 0xFFu) && head[1] == (kStartMarker >> 8);
}

std::unique_ptr<SurveyFileSink> create_survey_writer(const SurveyWriterContext& c) {
  WriterOptions o;
  o.overwrite = true;  // inside the run's own fresh temporary directory
  return std::make_unique<JsfSurveyWriter>(c.dir, c.line_names, *c.frame, *c.sonar, o);
}

// Each ping: one sonar data message per side, a 16-byte message header, the 240-byte sonar data
// header and 2 bytes per sample (docs/jsf.md).
double estimated_bytes(const SonarConfig& sonar, const std::string& /*sample_format*/, double pings,
                       std::size_t /*lines*/) {
  const double samples = static_cast<double>(sonar.samples_per_channel);
  return pings * 2.0 * (16.0 + 240.0 + 2.0 * samples);
}

// The any-format source takes a JSF ping's time validity and layback where the Ping has them
// (registry/sidescan_source.hpp): a renamed field must not fall back to "valid, no layback".
static_assert(requires(const Ping& p) {
  p.time_valid;
  p.layback_m;
});

}  // namespace

const SonarFormat& sonar_format() {
  static const SonarFormat format = reading_and_simulating_format(
      "jsf", "JSF", "EdgeTech JSF (Discover sonar data file)", {".jsf"}, identify,
      open_ping_source<Reader, Ping, sonar_format>, file_info, create_survey_writer,
      estimated_bytes, {{"xtf", "jsf", xtf_to_jsf}, {"jsf", "xtf", jsf_to_xtf}});
  return format;
}

}  // namespace sonarsynth::jsf
