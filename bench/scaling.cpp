// SPDX-License-Identifier: MIT
// Scaling of the whole per-ping pipeline (Simulator::run, speckle noise, truth on, the paper
// scene's sonar: the standard workload) and its peak memory. Each mode prints CSV rows to stdout
// (with --header, the header first); memory modes are meant to run one configuration per process
// (peak RSS from getrusage is per process).
//
//   scaling samples [--runs R]    pings/s vs samples per channel (512-16384) and threads (1, 2)
//   scaling objects [--runs R]    pings/s vs number of objects (0-10,000) on the paper scene
//   scaling grid --cells N        pings/s and peak RSS for a generated N-cell grid (0.25 m)
//   scaling length --lines N      peak RSS and pings/s for a survey of N x 400 m lines
//   scaling --tiny                a few-second smoke run of every mode (CI)
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_main.hpp"
#include "bench_metrics.hpp"
#include "bench_scenes.hpp"
#include "sonarsynth/bathy_gen.hpp"
#include "sonarsynth/formats/config/scene_file.hpp"
#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/simulator.hpp"

namespace {

using namespace sonarsynth;
using namespace bench;

constexpr double kPi = 3.14159265358979323846;

struct ChecksumSink : PingSink {
  std::uint64_t pings = 0;
  double sum = 0.0;
  void ping(const RenderedPing& p) override {
    ++pings;
    sum += p.port.samples[p.port.samples.size() / 2] + p.starboard.samples[0];
  }
};

// The standard workload's settings: the paper scene's sonar, speckle noise with K texture
// (SNR 25 dB), spherical TVG, u16 quantisation, truth on.
SimulationConfig standard_config(unsigned threads) {
  SimulationConfig c = bench_config(SceneKind::paper);
  c.noise.model = NoiseConfig::Model::kSpeckle;
  c.noise.snr_at_max_range_db = 25.0;
  c.output.tvg = TvgLaw::spherical;
  c.output.round_to_integer = true;
  c.truth = true;
  c.threads = threads;
  return c;
}

Survey line_survey(const Eigen::Vector2d& start, double length_m, int lines,
                   const SimulationConfig& c) {
  std::vector<SurveyLine> ls;
  for (int i = 0; i < lines; ++i) {
    SurveyLine l;
    l.name = "line" + std::to_string(i);
    const bool back = i % 2 == 1;
    const Eigen::Vector2d a = start, b = start + Eigen::Vector2d(length_m, 0.0);
    l.waypoints_xy_m =
        back ? std::vector<Eigen::Vector2d>{b, a} : std::vector<Eigen::Vector2d>{a, b};
    ls.push_back(l);
  }
  VehicleConfig v;
  v.speed_m_s = 2.0;
  v.altitude_m = 10.0;
  return Survey(ls, v, c.sonar.effective_ping_period_s(), UtcTime{}, 1);
}

// Median pings/s over `runs` runs.
double pings_per_s(const Scene& scene, const SimulationConfig& c, const Survey& survey, int runs,
                   int* planes_out = nullptr) {
  // Pilot pings of the automatic along-track plane count from the survey, as `simulate` does.
  const Simulator sim(scene, c, 10.0, pilot_poses(survey, scene.bathymetry));
  if (planes_out) *planes_out = sim.along_track().planes;
  std::vector<double> rate;
  for (int r = 0; r < runs; ++r) {
    ChecksumSink sink;
    const double t0 = now_s();
    sim.run(survey, sink);
    rate.push_back(static_cast<double>(sink.pings) / (now_s() - t0));
  }
  return median(rate);
}

const Scene& paper() {
  static const Scene s = load_scene(SONARSYNTH_SAMPLES_DIR "/paper_pipes.yaml");
  return s;
}

// Grid centre of the paper scene; its southern line runs 200 m south of it.
Eigen::Vector2d paper_line_start(double length_m) {
  const auto bb = paper().bathymetry.bounds();
  return Eigen::Vector2d(0.5 * (bb[0] + bb[2]) - 0.5 * length_m, 0.5 * (bb[1] + bb[3]) - 200.0);
}

void mode_samples(int runs, bool header, bool tiny) {
  if (header) std::printf("samples,threads,planes,pings,pings_per_s\n");
  const std::vector<std::size_t> counts =
      tiny ? std::vector<std::size_t>{512}
           : std::vector<std::size_t>{512, 1024, 2048, 4096, 8192, 16384};
  for (const std::size_t n : counts) {
    for (const unsigned t : {1u, 2u}) {
      SimulationConfig c = standard_config(t);
      c.sonar.samples_per_channel = n;
      const double len = tiny ? 10.0 : 200.0;
      const Survey s = line_survey(paper_line_start(len), len, 1, c);
      int planes = 0;
      const double rate = pings_per_s(paper(), c, s, runs, &planes);
      std::printf("%zu,%u,%d,%llu,%.1f\n", n, t, planes,
                  static_cast<unsigned long long>(s.total_pings()), rate);
      std::fflush(stdout);
    }
  }
}

void mode_objects(int runs, bool header, bool tiny) {
  if (header) std::printf("objects,threads,planes_setting,planes,pings,pings_per_s\n");
  const double len = tiny ? 10.0 : 200.0;
  const Eigen::Vector2d start = paper_line_start(len);
  for (const int count :
       tiny ? std::vector<int>{0, 10} : std::vector<int>{0, 10, 100, 1000, 10000}) {
    Scene s(paper().frame);
    s.bathymetry = paper().bathymetry;
    s.materials = paper().materials;
    s.material_map = paper().material_map;
    // Rocks (0.3-2 m) and short pipes (2-20 m, 0.2-1 m diameter) scattered uniformly over the
    // swaths (+-75 m) of the line.
    for (int k = 0; k < count; ++k) {
      const auto u = [&](std::uint64_t j) {
        return uniform_from_bits(keyed_hash(99, static_cast<std::uint64_t>(k), j));
      };
      ObjectPrimitive o;
      o.id = k + 1;
      o.centre_xy_m = start + Eigen::Vector2d(-10.0 + (len + 20.0) * u(0), -75.0 + 150.0 * u(1));
      o.heading_rad = 2.0 * kPi * u(2);
      if (k % 2 == 0) {
        o.shape = ObjectShape::kEllipsoid;
        const double r = 0.15 + 0.85 * u(3);
        o.half_extent_m = Eigen::Vector3d(r, r, 0.7 * r);
      } else {
        o.shape = ObjectShape::kCylinder;
        const double r = 0.1 + 0.4 * u(3);
        o.half_extent_m = Eigen::Vector3d(1.0 + 9.0 * u(4), r, r);
      }
      o.place_on_seabed(s.bathymetry, 0.0, 0.0, "object");
      s.objects.add(o);
    }
    s.objects.build_index();
    // The default (automatic plane count: objects smaller than the along-track footprint and
    // their shadows need more planes) and one plane (the cost of the objects themselves).
    for (const int setting : {QualityConfig::kAutoPlanes, 1}) {
      for (const unsigned t : {1u, 2u}) {
        SimulationConfig c = standard_config(t);
        c.quality.along_track_planes = setting;
        const Survey sv = line_survey(start, len, 1, c);
        int planes = 0;
        const double rate = pings_per_s(s, c, sv, runs, &planes);
        std::printf("%d,%u,%s,%d,%llu,%.1f\n", count, t, setting == 1 ? "1" : "auto", planes,
                    static_cast<unsigned long long>(sv.total_pings()), rate);
        std::fflush(stdout);
      }
    }
  }
}

void mode_grid(double cells, bool header) {
  if (header) std::printf("cells,grid_mib,generate_s,pings,pings_per_s,peak_rss_mib\n");
  const double cell = 0.25;
  const double side = std::sqrt(cells) * cell;
  BathyGenSpec spec;
  spec.depth_m = 20.0;
  spec.seed = 2017;
  spec.geometry = BathyGenSpec::centred_geometry(0.0, 0.0, side, side, cell);
  spec.components = {bathy::Fbm{.rms_m = 0.03, .base_wavelength_m = 8.0, .octaves = 1}};
  Scene s(paper().frame);
  const double t0 = now_s();
  s.bathymetry = generate_bathymetry(spec);
  const double gen = now_s() - t0;
  const SimulationConfig c = standard_config(2);
  const double len = std::min(200.0, side - 10.0);
  const Survey sv = line_survey(Eigen::Vector2d(-0.5 * len, 0.0), len, 1, c);
  const double rate = pings_per_s(s, c, sv, 3);
  std::printf("%zu,%.1f,%.2f,%llu,%.1f,%.1f\n", s.bathymetry.geometry().size(),
              static_cast<double>(s.bathymetry.geometry().size()) * 4.0 / 1048576.0, gen,
              static_cast<unsigned long long>(sv.total_pings()), rate, peak_rss_mib());
}

void mode_length(int lines, bool header) {
  if (header) std::printf("lines,survey_m,pings,pings_per_s,peak_rss_mib\n");
  const SimulationConfig c = standard_config(2);
  const Survey sv = line_survey(paper_line_start(400.0), 400.0, lines, c);
  const double rate = pings_per_s(paper(), c, sv, 1);
  std::printf("%d,%.0f,%llu,%.1f,%.1f\n", lines, 400.0 * lines,
              static_cast<unsigned long long>(sv.total_pings()), rate, peak_rss_mib());
}

int run(int argc, char** argv) {
  if (argc < 2) throw std::runtime_error("usage: scaling samples|objects|grid|length|--tiny ...");
  const std::string mode = argv[1];
  int runs = 3, lines = 1;
  double cells = 1e6;
  bool header = false;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    const auto next = [&] { return bench::value_after(i, argc, argv); };
    if (a == "--runs") {
      runs = std::stoi(next());
    } else if (a == "--cells") {
      cells = std::stod(next());
    } else if (a == "--lines") {
      lines = std::stoi(next());
    } else if (a == "--header") {
      header = true;
    } else {
      throw std::runtime_error("unknown argument " + a);
    }
  }
  if (mode == "samples") {
    mode_samples(runs, header, false);
  } else if (mode == "objects") {
    mode_objects(runs, header, false);
  } else if (mode == "grid") {
    mode_grid(cells, header);
  } else if (mode == "length") {
    mode_length(lines, header);
  } else if (mode == "--tiny") {
    mode_samples(1, true, true);
    mode_objects(1, true, true);
    mode_grid(1e5, true);
  } else {
    throw std::runtime_error("unknown mode " + mode);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main("scaling", run, argc, argv);
}
