// SPDX-License-Identifier: MIT
#pragma once

#include <cstdio>
#include <string>

#include "bench_metrics.hpp"
#include "bench_render.hpp"

namespace bench {

/// The CSV header of every stability sweep (bench/stability.cpp).
inline constexpr const char* kStabilityHeader =
    "sweep,x,family,label,rms_db,worst_db,edge_rms_db,edge_worst_db,empty_frac,nonfinite,bins,"
    "time_ms";

/// One row of a stability sweep: method m's errors e at abscissa x of `sweep`.
inline void stability_row(std::FILE* f, const char* sweep, double x, const Method& m,
                          const ErrorStats& e, double time_ms) {
  std::fprintf(f, "%s,%g,%s,%s,%.5g,%.5g,%.5g,%.5g,%.5g,%zu,%zu,%.5g\n", sweep, x, m.family.c_str(),
               m.label.c_str(), e.rms_db(), e.worst_db, e.edge_rms_db(), e.edge_worst_db,
               e.empty_fraction(), e.nonfinite, e.bins + e.edge_bins, time_ms);
}

/// Objects as closed sections (bench/stability_solids.cpp): writes stability_clearance.csv,
/// stability_pipe_size.csv and stability_object_grazing.csv under `dir`.
void sweep_solids(const std::string& dir, bool tiny);

}  // namespace bench
