// SPDX-License-Identifier: MIT
// The one list of sonar formats, and what iterates it: lookup by name, extension and content,
// the any-format reader, `info` and `convert` (docs/architecture.md, "Adding a sonar format").
#include "sonarsynth/formats/registry/sonar_formats.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <memory>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/atomic_file.hpp"
#include "sonarsynth/formats/jsf/convert.hpp"
#include "sonarsynth/formats/jsf/format.hpp"
#include "sonarsynth/formats/mcap/format.hpp"
#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/rosbag/format.hpp"
#include "sonarsynth/formats/xtf/format.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"

namespace sonarsynth {
namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

/// "XTF -> JSF, JSF -> XTF": every conversion of every format.
std::string conversion_pairs() {
  std::string out;
  for (const SonarFormat* f : sonar_formats()) {
    for (const SonarConversion& c : f->conversions) {
      if (!out.empty()) out += ", ";
      out += lower(c.from) + " -> " + lower(c.to);
    }
  }
  return out;
}

/// ".xtf, .jsf": the extensions of the formats some conversion writes.
std::string conversion_extensions() {
  std::string out;
  for (const SonarFormat* f : sonar_formats()) {
    bool written = false;
    for (const SonarFormat* g : sonar_formats()) {
      for (const SonarConversion& c : g->conversions) written = written || c.to == f->name;
    }
    if (!written) continue;
    for (std::string_view e : f->extensions) {
      if (!out.empty()) out += ", ";
      out += e;
    }
  }
  return out;
}

}  // namespace

std::span<const SonarFormat* const> sonar_formats() {
  // One line per format, in the order files are written and formats are tried (the first is
  // the default output of `simulate`). Explicit calls, not self-registering statics: a static
  // archive drops objects nothing references.
  static const SonarFormat* const kFormats[] = {
      &xtf::sonar_format(),
      &jsf::sonar_format(),
      &rosbag::sonar_format(),
      &mcap::sonar_format(),
  };
  return kFormats;
}

const SonarFormat* find_sonar_format(std::string_view name) {
  const std::string key = lower(name);
  for (const SonarFormat* f : sonar_formats()) {
    if (f->name == key) return f;
  }
  return nullptr;
}

std::string sonar_format_names(bool SonarFormatCapabilities::*capability) {
  std::string out;
  for (const SonarFormat* f : sonar_formats()) {
    if (capability != nullptr && !(f->capabilities.*capability)) continue;
    if (!out.empty()) out += ", ";
    out += f->name;
  }
  return out;
}

const SonarFormat& sonar_format_named(std::string_view name, std::string_view what) {
  const SonarFormat* f = find_sonar_format(name);
  if (!f) {
    throw InputError(std::string(what) + " = '" + std::string(name) +
                     "': unknown sonar format. Violated constraint: one of " +
                     sonar_format_names());
  }
  return *f;
}

const SonarFormat* sonar_format_for_extension(const std::filesystem::path& path) {
  const std::string ext = lower(path.extension().string());
  for (const SonarFormat* f : sonar_formats()) {
    for (std::string_view e : f->extensions) {
      if (e == ext) return f;
    }
  }
  return nullptr;
}

const SonarFormat* identify_sonar_format(const std::filesystem::path& path) {
  const auto source = xtf::open_file_source(path);
  std::array<std::uint8_t, SonarFormat::kIdentifyBytes> head{};
  const std::size_t n =
      static_cast<std::size_t>(std::min<std::uint64_t>(source->size(), head.size()));
  const std::span<std::uint8_t> bytes(head.data(), n);
  if (n > 0) source->read(0, bytes);
  for (const SonarFormat* f : sonar_formats()) {
    if (f->capabilities.read && f->identify(bytes)) return f;
  }
  return nullptr;
}

std::vector<std::string> sonar_format_extensions() {
  std::vector<std::string> out;
  for (const SonarFormat* f : sonar_formats()) {
    for (std::string_view e : f->extensions) out.emplace_back(e);
  }
  return out;
}

std::unique_ptr<SideScanSource> SideScanSource::open(const std::filesystem::path& path) {
  const SonarFormat* f = identify_sonar_format(path);
  return (f ? *f : *sonar_formats().front()).open_reader(path);
}

SonarFileInfo sonar_file_info(const std::filesystem::path& path, std::size_t max_anomalies) {
  const SonarFormat* f = identify_sonar_format(path);
  return (f ? *f : *sonar_formats().front()).info(path, max_anomalies);
}

ConvertResult convert_sonar_file(const std::filesystem::path& in, const std::filesystem::path& out,
                                 bool overwrite, AltitudeSource altitude_source) {
  const SonarFormat* to = sonar_format_for_extension(out);
  if (!to) {
    throw InputError("convert: output " + out.string() +
                     ": the extension names the output format. Violated constraint: one of " +
                     conversion_extensions());
  }
  const SonarFormat* from = identify_sonar_format(in);
  if (!from) {
    throw FormatError("convert: " + in.string() + ": not a file of any known format (" +
                      sonar_format_names(&SonarFormatCapabilities::read) + ")");
  }
  if (from == to) {
    throw InputError("convert: " + in.string() + " is already " + std::string(from->display_name) +
                     "; convert between " + conversion_pairs());
  }
  for (const SonarFormat* f : sonar_formats()) {
    for (const SonarConversion& c : f->conversions) {
      if (c.from == from->name && c.to == to->name) {
        return c.convert(in, out, overwrite, altitude_source);
      }
    }
  }
  throw InputError("convert: no conversion from " + std::string(from->display_name) + " to " +
                   std::string(to->display_name) + "; convert between " + conversion_pairs());
}

}  // namespace sonarsynth
