// SPDX-License-Identifier: MIT
// Mosaic gridding speed (docs/benchmarks.md, "Products at codec speed"): MosaicGrid::add on a
// simulate-like survey line (2 x 4096 samples over 75 m, 10 m altitude, 0.25 m pixels, a
// sloping seabed grid, labels, along-track fill), by runs of samples and point by point,
// alternately; and the gain normaliser's statistics and gains per ping. Thread CPU medians.
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "height_grid_test_util.hpp"  // tests/: the seabed sampled from a surface
#include "sonarsynth/bottom_track.hpp"
#include "sonarsynth/mosaic.hpp"

namespace {

using namespace sonarsynth;

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Survey {
  HeightGrid seabed;
  std::vector<float> port, stbd;
  std::vector<std::int32_t> port_labels, stbd_labels;
};

Survey make_survey(std::size_t samples) {
  GridGeometry g;
  g.dx_m = 0.5;
  g.dy_m = -0.5;
  g.cols = 801;
  g.rows = 801;
  g.x0_m = -200.0;
  g.y0_m = 200.0;
  const auto seabed = [](double x, double y) { return -20.0 + 0.02 * x + 0.3 * std::sin(0.1 * y); };
  Survey s{test::sampled_grid(g, seabed), {}, {}, {}, {}};
  std::mt19937 rng(7);
  std::exponential_distribution<float> e(1.0f);
  s.port.resize(samples);
  s.stbd.resize(samples);
  s.port_labels.resize(samples);
  s.stbd_labels.resize(samples);
  for (std::size_t i = 0; i < samples; ++i) {
    s.port[i] = e(rng);
    s.stbd[i] = e(rng);
    s.port_labels[i] = static_cast<std::int32_t>(i / 300);
    s.stbd_labels[i] = static_cast<std::int32_t>(i / 500);
  }
  return s;
}

/// Thread CPU seconds to grid `pings` pings; `image` gets the finished mosaic.
/// `bare`: a flat seabed and no along-track fill, so that add() is the ground ranges (a sqrt a
/// sample) and the gridding.
double grid_line(const Survey& s, int pings, bool runs, bool bare, MosaicImage& image) {
  MosaicOptions o;
  o.along_track_fill = !bare;
  MosaicGrid grid(MosaicGrid::geometry_covering({-180.0, -180.0}, {180.0, 180.0}, 0.25), o,
                  bare ? nullptr : &s.seabed);
  grid.set_sample_runs(runs);
  const double t0 = thread_cpu_s();
  for (int k = 0; k < pings; ++k) {
    MosaicPing m;
    m.sensor_xy_m = {-100.0 + 0.2 * k, 3.0 + 0.01 * k};
    m.heading_grid_rad = 1.55 + 0.002 * std::sin(0.05 * k);
    m.pitch_rad = 0.005 * std::sin(0.1 * k);
    m.altitude_m = 10.0;
    m.slant_range_m = 75.0;
    m.port = s.port;
    m.starboard = s.stbd;
    m.port_labels = s.port_labels;
    m.starboard_labels = s.stbd_labels;
    grid.add(m);
  }
  const double t = thread_cpu_s() - t0;
  image = std::move(grid).finish();
  return t;
}

bool same_bits(const MosaicImage& a, const MosaicImage& b) {
  return a.intensity.size() == b.intensity.size() &&
         std::memcmp(a.intensity.data(), b.intensity.data(), 4 * a.intensity.size()) == 0 &&
         a.count == b.count && a.labels == b.labels;
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 5;
  int pings = 1000;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--runs") runs = std::atoi(argv[i + 1]);
    if (a == "--pings") pings = std::atoi(argv[i + 1]);
  }
  if (runs < 1 || pings < 1) {
    std::fprintf(stderr, "usage: mosaic_benchmark [--runs N >= 1] [--pings N >= 1]\n");
    return 2;
  }
  const Survey s = make_survey(4096);
  std::vector<double> by_runs, by_point, bare_runs, bare_point, gain_add, gain_apply;
  bool same = true;
  for (int r = 0; r < runs; ++r) {
    MosaicImage a, b;
    by_point.push_back(grid_line(s, pings, false, false, b) / pings);
    by_runs.push_back(grid_line(s, pings, true, false, a) / pings);
    same = same && same_bits(a, b);
    bare_point.push_back(grid_line(s, pings, false, true, b) / pings);
    bare_runs.push_back(grid_line(s, pings, true, true, a) / pings);
    same = same && same_bits(a, b);
    GainNormaliser gain(GainNormalisation::kAngle);
    double t0 = thread_cpu_s();
    for (int k = 0; k < pings; ++k) gain.add_ping(s.port, s.stbd, 75.0, 10.0 + 0.001 * k);
    gain_add.push_back((thread_cpu_s() - t0) / pings);
    gain.finish();
    std::vector<float> p = s.port, q = s.stbd;
    t0 = thread_cpu_s();
    for (int k = 0; k < pings; ++k) gain.apply(p, q, 75.0, 10.0 + 0.001 * k);
    gain_apply.push_back((thread_cpu_s() - t0) / pings);
  }
  std::printf(
      "mosaic gridding, sloping seabed grid, along-track fill, %d pings x 2 x 4096 samples, median "
      "of %d runs (thread CPU):\n",
      pings, runs);
  std::printf("  point by point   %7.1f us/ping\n", 1e6 * median(by_point));
  std::printf("  runs of samples  %7.1f us/ping  (%.2fx)\n", 1e6 * median(by_runs),
              median(by_point) / median(by_runs));
  std::printf("flat seabed, no along-track fill (ground ranges + gridding):\n");
  std::printf("  point by point   %7.1f us/ping\n", 1e6 * median(bare_point));
  std::printf("  runs of samples  %7.1f us/ping  (%.2fx)\n", 1e6 * median(bare_runs),
              median(bare_point) / median(bare_runs));
  std::printf("gain normaliser (angle bins): statistics %.1f us/ping, gains %.1f us/ping\n",
              1e6 * median(gain_add), 1e6 * median(gain_apply));
  std::printf("images by runs and point by point: %s\n", same ? "bit-identical" : "DIFFER");
  return same ? 0 : 1;
}
