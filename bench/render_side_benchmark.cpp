// SPDX-License-Identifier: MIT
// One side of one ping: 4096 samples over 75 m, rough seabed profile (0.25 m or 0.05 m node
// spacing), Lambert + spreading + absorption + Gaussian vertical beam, truth off / on.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>

#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/render_side.hpp"

namespace {

using namespace sonarsynth;

// Rough seabed: two sinusoids plus keyed per-node jitter, sensor 10 m above the mean.
BeamProfile rough_profile(double spacing_m, double length_m) {
  BeamProfile p;
  p.sensor_z_m = 10.0;
  const auto n = static_cast<std::size_t>(length_m / spacing_m);
  for (std::size_t i = 0; i <= n; ++i) {
    const double y = static_cast<double>(i) * spacing_m;
    const double jitter = 0.05 * (uniform_from_bits(keyed_hash(1, i, 0)) - 0.5);
    p.add_node(y, 0.5 * std::sin(2.0 * 3.14159265 * y / 8.0) +
                      0.3 * std::sin(2.0 * 3.14159265 * y / 3.1) + jitter);
  }
  return p;
}

void BM_RenderSide(benchmark::State& state) {
  const double spacing = static_cast<double>(state.range(0)) / 100.0;
  const bool truth = state.range(1) != 0;
  const BeamProfile prof = rough_profile(spacing, 75.0);
  SideParams p;
  p.samples = 4096;
  p.sample_spacing_m = 75.0 / 4096.0;
  p.vertical_beam.shape = VerticalBeamShape::gaussian;
  p.vertical_beam.width_3db_rad = 50.0 * 3.14159265358979 / 180.0;
  p.absorption_db_per_m = 0.096;
  p.truth = truth;
  SideEcho echo;
  for (auto _ : state) {
    render_side(prof, p, echo);
    benchmark::DoNotOptimize(echo.intensity.data());
  }
  state.counters["nodes"] = static_cast<double>(prof.nodes());
}
BENCHMARK(BM_RenderSide)
    ->ArgNames({"spacing_cm", "truth"})
    ->Args({25, 0})
    ->Args({25, 1})
    ->Args({5, 0})
    ->Args({5, 1})
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
