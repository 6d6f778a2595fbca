// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace sonarsynth {

struct SonarFormat;

/// What a conversion (SonarConversion::convert, `sonarsynth convert`) did: pings written and
/// dropped, fields repaired (docs/conversion.md, "Drops and repairs"). Every codec's conversions
/// return it, so it lives beside the format descriptor.
struct ConvertResult {
  const SonarFormat* from = nullptr;   ///< the input's format (sonar_formats())
  const SonarFormat* to = nullptr;     ///< the output's format
  std::uint64_t pings = 0;             ///< pings written
  std::uint64_t attitude_records = 0;  ///< attitude packets/messages written
  std::uint64_t pings_skipped = 0;     ///< pings dropped (counted by reason in `dropped`)
  std::uint64_t reader_anomalies = 0;
  std::uint64_t pings_tracked_altitude = 0;  ///< altitude replaced by the tracked one
  std::vector<std::string> warnings;         ///< the first kMaxWarnings drops and anomalies
  /// Pings dropped, by reason (docs/conversion.md, "Drops"); the counts add up to pings_skipped.
  std::map<std::string, std::uint64_t> dropped;
  /// Fields written as the output's "unknown" (or neutral 0), by rule (docs/conversion.md,
  /// "Repairs"); one ping may count under several rules.
  std::map<std::string, std::uint64_t> repaired;

  static constexpr std::size_t kMaxWarnings = 10;
  /// Keeps `message` if fewer than kMaxWarnings are kept.
  void warn(std::string message) {
    if (warnings.size() < kMaxWarnings) warnings.push_back(std::move(message));
  }
};

}  // namespace sonarsynth
