// SPDX-License-Identifier: MIT
// Whole per-ping pipeline (docs/benchmarks.md): the founding paper's
// pipe scene (samples/paper_pipes.yaml, 0.25 m grid), the default SimulationConfig (2 x 4096
// samples at 75 m, shadows, sonar equation, speckle with K texture and thermal noise, truth on),
// one 400 m line 40 m inside the square of pipes. Reports pings/s (median of the runs) for each
// thread count and the per-stage CPU split returned by Simulator::run.
//
// Usage: ping_benchmark [scene.yaml] [--runs N] [--threads a,b,...] [--length-m L] [--no-truth]
//                       [--noise none|paper|speckle] [--planes K] [--dump FILE]
//                       [--beam-deg B] [--sonar PRESET]
// --planes fixes the along-track plane count (default: automatic). --beam-deg sets the horizontal
// beam (default 1 deg; at 0.5 deg the along-track speckle lattice applies, pings 0.2 m apart).
// --sonar replaces the default sonar by a preset of docs/sonar-presets.md (seascan-hds-600: a pulse
// longer than a sample, so the range-filtered detector runs).
// --dump writes every ping of the last run (samples, truth class, label, grazing angle) as raw
// little-endian arrays, for bit-level comparison of two builds.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_main.hpp"
#include "sonarsynth/formats/config/scene_file.hpp"
#include "sonarsynth/simulator.hpp"
#include "sonarsynth/sonar_presets.hpp"

namespace {

using namespace sonarsynth;

// Consumes the pings and folds every sample into a checksum (identical for any thread count).
struct ChecksumSink : PingSink {
  std::uint64_t pings = 0;
  double sum = 0.0;
  std::ofstream* dump = nullptr;
  void ping(const RenderedPing& p) override {
    ++pings;
    for (const float v : p.port.samples) sum += v;
    for (const float v : p.starboard.samples) sum += v;
    if (dump != nullptr) {
      for (const SideOutput* s : {&p.port, &p.starboard}) {
        write(s->samples);
        write(s->truth_class);
        write(s->truth_label);
        write(s->truth_grazing_rad);
      }
    }
  }
  template <class T>
  void write(const std::vector<T>& v) {
    dump->write(reinterpret_cast<const char*>(v.data()),
                static_cast<std::streamsize>(v.size() * sizeof(T)));
  }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int run(int argc, char** argv) {
  std::string path = SONARSYNTH_SAMPLES_DIR "/paper_pipes.yaml";
  int runs = 5;
  std::vector<unsigned> thread_counts = {1, 2};
  double length_m = 400.0;
  std::string dump_path;
  SimulationConfig cfg;  // defaults: speckle + texture, 4096 samples, 75 m, shadows, truth
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto next = [&] { return bench::value_after(i, argc, argv); };
    if (a == "--runs") {
      runs = std::max(1, std::stoi(next()));
    } else if (a == "--threads") {
      thread_counts.clear();
      std::stringstream ss(next());
      std::string tok;
      while (std::getline(ss, tok, ','))
        thread_counts.push_back(static_cast<unsigned>(std::stoul(tok)));
    } else if (a == "--length-m") {
      length_m = std::stod(next());
    } else if (a == "--no-truth") {
      cfg.truth = false;
    } else if (a == "--beam-deg") {  // horizontal beam (0.5: the along-track lattice applies)
      cfg.sonar.horizontal_beam_width_rad = std::stod(next()) * (3.14159265358979323846 / 180.0);
    } else if (a == "--sonar") {
      cfg.sonar = sonar_preset(next());
    } else if (a == "--planes") {
      cfg.quality.along_track_planes = std::stoi(next());
    } else if (a == "--float") {  // unrounded samples (for the accuracy of --dump)
      cfg.output.round_to_integer = false;
    } else if (a == "--dump") {
      dump_path = next();
    } else if (a == "--noise") {
      const std::string m = next();
      cfg.noise.model = m == "none"    ? NoiseConfig::Model::kNone
                        : m == "paper" ? NoiseConfig::Model::kPaper
                                       : NoiseConfig::Model::kSpeckle;
    } else {
      path = a;
    }
  }

  const Scene scene = load_scene(path);
  const auto bb = scene.bathymetry.bounds();
  const Eigen::Vector2d c(0.5 * (bb[0] + bb[2]), 0.5 * (bb[1] + bb[3]));
  // The scene's pipes form a square of half-side 240 m around the grid centre; the line runs
  // along its southern side, 40 m inside.
  SurveyLine line;
  line.name = "south";
  line.waypoints_xy_m = {c + Eigen::Vector2d(-0.5 * length_m, -200.0),
                         c + Eigen::Vector2d(0.5 * length_m, -200.0)};
  VehicleConfig vehicle;
  vehicle.speed_m_s = 2.0;
  vehicle.altitude_m = 10.0;
  const Survey survey({line}, vehicle, cfg.sonar.effective_ping_period_s(), UtcTime{}, 1);

  std::printf("scene %s, %llu pings of 2 x %zu samples, %g m range, truth %s\n", path.c_str(),
              static_cast<unsigned long long>(survey.total_pings()), cfg.sonar.samples_per_channel,
              cfg.sonar.max_range_m, cfg.truth ? "on" : "off");
  for (const unsigned threads : thread_counts) {
    cfg.threads = threads;
    // The automatic along-track plane count from pilot pings of the survey, as `simulate` does
    // (its one-off cost is reported, not included in pings/s).
    const Simulator sim(scene, cfg, 10.0, pilot_poses(survey, scene.bathymetry));
    std::printf("along-track planes %d (auto: %s, estimated error %.3f dB, pilot %.1f ms)\n",
                sim.along_track().planes, sim.along_track().automatic ? "yes" : "no",
                sim.along_track().estimated_error_db, 1e3 * sim.along_track().pilot_s);
    if (sim.along_track().object_planes > sim.along_track().planes) {
      std::printf(
          "  %d planes over the range window of objects and shadows (estimated error with "
          "objects %.3f dB)\n",
          sim.along_track().object_planes, sim.along_track().object_estimated_error_db);
    }
    std::vector<double> rate, profile_us, render_us, noise_us;
    double checksum = 0.0;
    std::uint64_t window_sides = 0, window_samples = 0;
    for (int r = 0; r < runs; ++r) {
      ChecksumSink sink;
      std::ofstream dump;
      if (!dump_path.empty() && r + 1 == runs) {
        dump.open(dump_path, std::ios::binary);
        if (!dump) throw std::runtime_error("cannot write " + dump_path);
        sink.dump = &dump;
      }
      const auto t0 = std::chrono::steady_clock::now();
      const RenderTimings tm = sim.run(survey, sink);
      const double dt =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const auto n = static_cast<double>(sink.pings);
      rate.push_back(n / dt);
      profile_us.push_back(tm.profile_s / n * 1e6);
      render_us.push_back(tm.render_s / n * 1e6);
      noise_us.push_back(tm.noise_s / n * 1e6);
      checksum = sink.sum;
      window_sides = tm.window_sides;
      window_samples = tm.window_samples;
    }
    std::printf(
        "threads %u: %8.0f pings/s (median of %d; min %.0f, max %.0f) | CPU per ping (both "
        "sides): profile %7.1f us, render %7.1f us, noise+tvg %7.1f us | checksum %.17g\n",
        threads, median(rate), runs, *std::min_element(rate.begin(), rate.end()),
        *std::max_element(rate.begin(), rate.end()), median(profile_us), median(render_us),
        median(noise_us), checksum);
    if (window_sides > 0) {
      std::printf("  object windows: %llu ping sides, %.0f samples each on average\n",
                  static_cast<unsigned long long>(window_sides),
                  static_cast<double>(window_samples) / static_cast<double>(window_sides));
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main("ping_benchmark", run, argc, argv);
}
