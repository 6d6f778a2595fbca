// SPDX-License-Identifier: MIT
// Microbenchmark of the along-track speckle lattice (docs/physics.md §1.6): thread CPU time of
// along_track_speckle_looks per sample of one ping side, over consecutive pings of one side, with
// the paper scene's sonar (400 kHz, 0.5 deg beam, translated aperture, 2 x 4096 samples at 75 m,
// 2 m/s at 10 pings/s). The path is SONARSYNTH_SIMD's (scalar, avx2, avx512; default the best).
//
// Usage: lattice_benchmark [--pings N] [--reps R] [--looks L] [--spacing-m D]
// (the pings D apart; at D > 0.34 m the lattice applies nowhere).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "sonarsynth/sensor_effects.hpp"
#include "sonarsynth/simd.hpp"

namespace {
double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
}  // namespace

int main(int argc, char** argv) {
  int pings = 400, reps = 7, looks = 3;
  double spacing_m = 0.2;
  for (int a = 1; a < argc; ++a) {
    const std::string s = argv[a];
    const auto next = [&] { return a + 1 < argc ? std::string(argv[++a]) : std::string("0"); };
    if (s == "--pings") {
      pings = std::stoi(next());
    } else if (s == "--reps") {
      reps = std::stoi(next());
    } else if (s == "--looks") {
      looks = std::stoi(next());
    } else if (s == "--spacing-m") {
      spacing_m = std::stod(next());
    }
  }
  sonarsynth::simd::configure_from_environment();
  const std::size_t samples = 4096;
  sonarsynth::AlongTrackField f;
  f.key = 12345;
  f.seed = 7;
  f.sample_spacing_m = 75.0 / static_cast<double>(samples);
  f.beam_3db_rad = 0.5 * 3.14159265358979323846 / 180.0;
  f.array_length_m = 0.886 * (1500.0 / 400e3) / f.beam_3db_rad;
  f.first_sample = static_cast<std::size_t>(10.0 / f.sample_spacing_m);
  f.ping_spacing_m = spacing_m;
  std::vector<double> out, times;
  double sink = 0.0;
  for (int r = 0; r < reps; ++r) {
    sonarsynth::AlongTrackTable table;
    const double t0 = thread_cpu_s();
    for (int p = 0; p < pings; ++p) {
      f.along_track_m = 100.0 + spacing_m * static_cast<double>(p);
      sonarsynth::along_track_speckle_looks(f, samples, 0, looks, table, out);
      sink += out[samples / 2];
    }
    times.push_back((thread_cpu_s() - t0) / (static_cast<double>(pings) * samples));
  }
  std::sort(times.begin(), times.end());
  std::printf(
      "lattice %s: %d looks, spacing %g m: %.2f ns/sample (median of %d; min %.2f)"
      " [%g]\n",
      std::string(sonarsynth::simd::target_name(sonarsynth::simd::active_target())).c_str(), looks,
      spacing_m, 1e9 * times[times.size() / 2], reps, 1e9 * times[0], sink);
  return 0;
}
