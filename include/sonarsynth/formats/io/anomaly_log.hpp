// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace sonarsynth {

/// What a format's reader found wrong in a file: a count per kind and the first anomalies in
/// full. `Anomaly` has a `kind`, an enum of `KindCount` values from 0; the XTF and JSF readers
/// derive from it.
template <class Anomaly, std::size_t KindCount>
class AnomalyLog {
 public:
  using Kind = decltype(Anomaly::kind);

  const std::vector<Anomaly>& anomalies() const { return anomalies_; }
  std::uint64_t anomaly_count(Kind kind) const { return counts_[static_cast<std::size_t>(kind)]; }
  /// anomaly_count of every kind, indexed by the kind's value.
  const std::array<std::uint64_t, KindCount>& anomaly_counts() const { return counts_; }
  std::uint64_t total_anomalies() const {
    std::uint64_t n = 0;
    for (const std::uint64_t c : counts_) n += c;
    return n;
  }

 protected:
  /// Counts `anomaly`, and keeps it while fewer than `max_kept` are kept.
  void log_anomaly(Anomaly anomaly, std::size_t max_kept) {
    ++counts_[static_cast<std::size_t>(anomaly.kind)];
    if (anomalies_.size() < max_kept) anomalies_.push_back(std::move(anomaly));
  }

 private:
  std::vector<Anomaly> anomalies_;
  std::array<std::uint64_t, KindCount> counts_{};
};

}  // namespace sonarsynth
