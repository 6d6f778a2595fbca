// SPDX-License-Identifier: MIT
#include "bench_metrics.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace bench {

namespace {

/// kFloorRel x the median of the non-zero bins of ref[b0, b1); none when all are zero.
std::optional<double> block_floor(const std::vector<double>& ref, std::size_t b0, std::size_t b1) {
  std::vector<double> lit;
  for (std::size_t i = b0; i < b1; ++i)
    if (ref[i] > 0.0) lit.push_back(ref[i]);
  if (lit.empty()) return std::nullopt;
  return kFloorRel * median(lit);
}

/// The method filled the bin (finite and above 1e-4 of the reference).
bool filled(double got, double ref) {
  return std::isfinite(got) && got > 1e-4 * ref;
}

/// |10 log10(got / ref)| capped at kCapDb; kCapDb for a bin the method did not fill.
double error_db(double got, double ref) {
  return filled(got, ref) ? std::min(kCapDb, std::abs(10.0 * std::log10(got / ref))) : kCapDb;
}

/// Bin i is next to a bin of its block below the floor (a shadow or first-return edge).
bool at_edge(const std::vector<double>& ref, std::size_t i, std::size_t b0, std::size_t b1,
             double floor) {
  return (i > b0 && !(ref[i - 1] >= floor)) || (i + 1 < b1 && !(ref[i + 1] >= floor));
}

}  // namespace

void ErrorStats::add(const std::vector<double>& got, const std::vector<double>& ref,
                     std::size_t block) {
  for (std::size_t b0 = 0; b0 < ref.size(); b0 += block) {
    const std::size_t b1 = std::min(ref.size(), b0 + block);
    const std::optional<double> floor = block_floor(ref, b0, b1);
    if (!floor) continue;
    for (std::size_t i = b0; i < b1; ++i) {
      if (!std::isfinite(got[i]) || got[i] < 0.0) ++nonfinite;
      if (!(ref[i] >= *floor)) continue;
      const double e = error_db(got[i], ref[i]);
      if (!filled(got[i], ref[i])) ++empty;
      if (at_edge(ref, i, b0, b1, *floor)) {
        edge_sum_sq_db += e * e;
        edge_worst_db = std::max(edge_worst_db, e);
        ++edge_bins;
      } else {
        sum_sq_db += e * e;
        worst_db = std::max(worst_db, e);
        ++bins;
      }
    }
  }
}

void worst_bins(const std::vector<double>& got, const std::vector<double>& ref, std::size_t block,
                std::size_t count, std::size_t offset, std::vector<BinError>& out) {
  for (std::size_t b0 = 0; b0 < ref.size(); b0 += block) {
    const std::size_t b1 = std::min(ref.size(), b0 + block);
    const std::optional<double> floor = block_floor(ref, b0, b1);
    if (!floor) continue;
    for (std::size_t i = b0; i < b1; ++i) {
      if (!(ref[i] >= *floor)) continue;
      out.push_back({error_db(got[i], ref[i]), offset + i, at_edge(ref, i, b0, b1, *floor)});
    }
  }
  std::sort(out.begin(), out.end(),
            [](const BinError& a, const BinError& b) { return a.error_db > b.error_db; });
  if (out.size() > count) out.resize(count);
}

double ErrorStats::rms_db() const {
  return bins ? std::sqrt(sum_sq_db / static_cast<double>(bins)) : 0.0;
}
double ErrorStats::edge_rms_db() const {
  return edge_bins ? std::sqrt(edge_sum_sq_db / static_cast<double>(edge_bins)) : 0.0;
}
double ErrorStats::all_rms_db() const {
  const std::size_t n = bins + edge_bins;
  return n ? std::sqrt((sum_sq_db + edge_sum_sq_db) / static_cast<double>(n)) : 0.0;
}
double ErrorStats::empty_fraction() const {
  const std::size_t n = bins + edge_bins;
  return n ? static_cast<double>(empty) / static_cast<double>(n) : 0.0;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double peak_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // Linux: KiB
}

std::vector<bool> pareto_front(const std::vector<double>& time, const std::vector<double>& error,
                               double time_tolerance) {
  std::vector<bool> front(time.size(), true);
  for (std::size_t i = 0; i < time.size(); ++i)
    for (std::size_t j = 0; j < time.size(); ++j)
      if (j != i && time[j] <= time[i] && error[j] <= error[i] &&
          (error[j] < error[i] || time[j] < (1.0 - time_tolerance) * time[i])) {
        front[i] = false;
        break;
      }
  return front;
}

std::FILE* open_csv(const std::string& path, const char* header) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path);
  std::fprintf(f, "%s\n", header);
  return f;
}

}  // namespace bench
