// SPDX-License-Identifier: MIT
// The C++ side of the Python module's tests and benchmark (docs/python.md): renders the survey
// poses of a scene file with a Simulator built as run_simulation builds it, on one thread.
//   python_render_reference dump SCENE OUT.bin [FIRST COUNT]
//     writes per ping, port then starboard, S = samples per side: samples (float32 x S),
//     truth class (uint8 x S), object id (int32 x S), grazing (float32 x S), ground x and y
//     (float64 x S each), native byte order.
//   python_render_reference bench SCENE PINGS REPEATS
//     renders the first PINGS poses REPEATS times; prints pings/s of each repeat (wall and thread
//     CPU time) and the medians.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <exception>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "sonarsynth/formats/config/simulation_file.hpp"
#include "sonarsynth/simulator.hpp"

namespace {

using namespace sonarsynth;

template <class V>
void write(std::ofstream& out, const V& v) {
  out.write(reinterpret_cast<const char*>(v.data()),
            static_cast<std::streamsize>(v.size() * sizeof(v[0])));
}

int run(int argc, char** argv) {
  if (argc < 4) {
    std::cerr << "usage: python_render_reference dump SCENE OUT.bin [FIRST COUNT] | bench SCENE "
                 "PINGS REPEATS\n";
    return 2;
  }
  const std::string mode = argv[1];
  const auto setup = std::make_shared<const SimulationSetup>(load_simulation(argv[2]));
  const std::shared_ptr<const Scene> scene(setup, &setup->scene);
  const Survey survey = setup->make_survey();
  const Simulator sim(scene, setup->config, setup->reference_altitude_m,
                      pilot_poses(survey, scene->bathymetry));
  auto ws = sim.make_workspace();
  RenderedPing ping;
  if (mode == "dump") {
    std::uint64_t first = argc > 5 ? std::stoull(argv[4]) : 0;
    std::uint64_t count = argc > 5 ? std::stoull(argv[5]) : survey.total_pings();
    std::ofstream out(argv[3], std::ios::binary);
    for (std::uint64_t i = first; i < first + count && i < survey.total_pings(); ++i) {
      sim.render_ping(survey.pose(i, scene->bathymetry), *ws, ping);
      for (const SideOutput* s : {&ping.port, &ping.starboard}) {
        write(out, s->samples);
        write(out, s->truth_class);
        write(out, s->truth_label);
        write(out, s->truth_grazing_rad);
        std::vector<double> x(s->truth_ground_range_m.size()), y(x.size());
        s->truth_ground_positions(x.data(), y.data());
        write(out, x);
        write(out, y);
      }
    }
    return out ? 0 : 1;
  }
  if (mode == "bench" && argc > 4) {
    const std::uint64_t pings = std::min<std::uint64_t>(std::stoull(argv[3]), survey.total_pings());
    const int repeats = std::stoi(argv[4]);
    std::vector<PingPose> poses;
    for (std::uint64_t i = 0; i < pings; ++i) poses.push_back(survey.pose(i, scene->bathymetry));
    sim.render_ping(poses.front(), *ws, ping);  // warm the workspace
    // Wall time and this thread's CPU time (the machine may be shared: CPU time is what the
    // rendering itself costs).
    const auto cpu_s = [] {
      timespec t{};
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
      return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
    };
    std::vector<double> rates, cpu_rates;
    for (int r = 0; r < repeats; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      const double c0 = cpu_s();
      for (const PingPose& p : poses) sim.render_ping(p, *ws, ping);
      const double c1 = cpu_s();
      const std::chrono::duration<double> dt = std::chrono::steady_clock::now() - t0;
      rates.push_back(static_cast<double>(pings) / dt.count());
      cpu_rates.push_back(static_cast<double>(pings) / (c1 - c0));
      std::printf("repeat %d: %.2f pings/s wall, %.2f pings/s cpu\n", r, rates.back(),
                  cpu_rates.back());
    }
    std::sort(rates.begin(), rates.end());
    std::sort(cpu_rates.begin(), cpu_rates.end());
    std::printf("median: %.3f pings/s wall, %.3f pings/s cpu\n", rates[rates.size() / 2],
                cpu_rates[cpu_rates.size() / 2]);
    return 0;
  }
  std::cerr << "python_render_reference: unknown mode '" << mode << "'\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "python_render_reference: " << e.what() << "\n";
    return 1;
  }
}
