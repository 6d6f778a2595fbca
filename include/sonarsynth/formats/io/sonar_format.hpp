// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sonarsynth/bottom_track.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/ping_sink.hpp"
#include "sonarsynth/sonar.hpp"

namespace sonarsynth {

class Simulator;
class SideScanSource;
struct ConvertResult;

/// A format's survey writer: a PingSink writing one file per survey line into a directory.
class SurveyFileSink : public PingSink {
 public:
  /// Files written so far (final paths), in the order the lines finished.
  virtual const std::vector<std::filesystem::path>& files() const = 0;
  /// Settings some common reader of the format does not accept (empty if none).
  virtual std::vector<std::string> compatibility_warnings() const { return {}; }
};

/// What `simulate` hands to a format's create_survey_writer: where the files go, and every
/// setting of the run that a format may store in its headers.
struct SurveyWriterContext {
  std::filesystem::path dir;             ///< the files go to dir / (line name + extension)
  std::vector<std::string> line_names;   ///< one per survey line
  const GeoFrame* frame = nullptr;       ///< the scene's local frame (for WGS 84 positions)
  const SonarConfig* sonar = nullptr;    ///< the sonar of the run
  const Simulator* simulator = nullptr;  ///< the run's configuration, gain and TVG
  std::string scene_name;
  std::string sample_format = "u16";  ///< output.sample_format: u16, u8 or f32
  bool allow_more_than_8192_samples = false;
  /// output.bag_truth: the ROS bag formats also write each ping's truth on topics of their own
  /// (docs/robotics.md, "Truth topics"); the run renders with truth (checked when it is read).
  bool bag_truth = false;
};

/// What `sonarsynth info` prints about a file, made by the file's format (the CLI prints it,
/// Python returns it).
struct SonarFileInfo {
  std::string json;  ///< one JSON object (ASCII), "format" first
  std::string text;  ///< human-readable, several lines, each ending in '\n'
};

/// What a format can do; each flag says which of SonarFormat's functions are set.
struct SonarFormatCapabilities {
  bool read = false;      ///< open_reader, identify, info: info, waterfall, mosaic, match, Python
  bool simulate = false;  ///< create_survey_writer, estimated_bytes: `simulate` (output.formats)
};

/// A conversion a format provides between itself and another format (`convert`).
struct SonarConversion {
  std::string_view from;  ///< SonarFormat::name of the input
  std::string_view to;    ///< SonarFormat::name of the output
  /// Converts `in` into `out` (docs/conversion.md); the output is written atomically.
  ConvertResult (*convert)(const std::filesystem::path& in, const std::filesystem::path& out,
                           bool overwrite, AltitudeSource altitude_source) = nullptr;
};

/// One sonar file format, as GDAL describes a driver: its names, file extensions, how to
/// recognise a file of it, and the functions that read, write, convert and summarise it. Each
/// codec defines one (formats/<codec>/format.cpp); formats/registry/sonar_formats.cpp lists them
/// all, one explicit line each (docs/architecture.md, "Adding a sonar format").
struct SonarFormat {
  /// How many leading bytes of a file identify() is given (fewer if the file is shorter).
  static constexpr std::size_t kIdentifyBytes = 16;

  std::string_view name;                     ///< lower-case key: output.formats, Python's "format"
  std::string_view display_name;             ///< as users write it: "XTF"
  std::string_view description;              ///< one line: the format's full name and owner
  std::vector<std::string_view> extensions;  ///< lower case with the dot; the first is written
  SonarFormatCapabilities capabilities;

  /// True if a file starting with `head` (at most kIdentifyBytes bytes) is of this format.
  bool (*identify)(std::span<const std::uint8_t> head) = nullptr;
  /// The pings of `path`. Throws FormatError if it cannot be opened or read.
  std::unique_ptr<SideScanSource> (*open_reader)(const std::filesystem::path& path) = nullptr;
  /// Summary of `path` for `info`, listing at most `max_anomalies` anomaly messages in the text.
  SonarFileInfo (*info)(const std::filesystem::path& path, std::size_t max_anomalies) = nullptr;
  /// The survey writer of `simulate`. Throws InputError for settings the format cannot hold.
  std::unique_ptr<SurveyFileSink> (*create_survey_writer)(const SurveyWriterContext& context) =
      nullptr;
  /// Upper bound of the bytes `simulate` writes in this format for `pings` pings over `lines`
  /// lines (the run check's disk estimate).
  double (*estimated_bytes)(const SonarConfig& sonar, const std::string& sample_format,
                            double pings, std::size_t lines) = nullptr;
  /// The conversions this format's codec provides (to or from it); `convert` looks for the
  /// pair in every format's list.
  std::vector<SonarConversion> conversions;
};

/// The descriptor of a format that reads and simulates: both capabilities, with the codec's
/// functions for them (every one set) and its conversions.
inline SonarFormat reading_and_simulating_format(
    std::string_view name, std::string_view display_name, std::string_view description,
    std::vector<std::string_view> extensions, decltype(SonarFormat::identify) identify,
    decltype(SonarFormat::open_reader) open_reader, decltype(SonarFormat::info) info,
    decltype(SonarFormat::create_survey_writer) create_survey_writer,
    decltype(SonarFormat::estimated_bytes) estimated_bytes,
    std::vector<SonarConversion> conversions) {
  return {.name = name,
          .display_name = display_name,
          .description = description,
          .extensions = std::move(extensions),
          .capabilities = {.read = true, .simulate = true},
          .identify = identify,
          .open_reader = open_reader,
          .info = info,
          .create_survey_writer = create_survey_writer,
          .estimated_bytes = estimated_bytes,
          .conversions = std::move(conversions)};
}

}  // namespace sonarsynth
