// SPDX-License-Identifier: MIT
// sonarsynth: synthetic side-scan sonar survey data. `sonarsynth --help` lists the subcommands.
#include <boost/program_options/errors.hpp>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>
#include <vector>

#include "commands.hpp"
#include "interrupt.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/simd.hpp"
#include "sonarsynth/version.hpp"

namespace sc = sonarsynth::cli;

namespace {

const std::vector<sc::Command>& commands() {
  static const std::vector<sc::Command> table = {
      {"simulate", "render a scene file's survey into XTF files (+ mosaic, waterfalls, truth)",
       sc::run_simulate},
      {"dataset", "render N scenes drawn from a dataset spec (resumable, --shard K/N)",
       sc::run_dataset},
      {"version", "print the version and exit", sc::run_version},
      {"info",
       "describe a sonar file of any known format (header, channels, pings, nav, anomalies)",
       sc::run_info},
      {"convert",
       "convert a side-scan file into another sonar format (the conversions: convert --help)",
       sc::run_convert},
      {"bathy", "generate bathymetry (plane, ripples, fBm, seamount, scarp) as a GeoTIFF",
       sc::run_bathy},
      {"mosaic", "grid sonar files into a georeferenced GeoTIFF mosaic (+ RGB display copy)",
       sc::run_mosaic},
      {"waterfall", "draw a sonar file as a port | starboard waterfall image", sc::run_waterfall},
      {"match", "feature matching between two sonar images (SIFT, BRISK, ORB, A-KAZE; OpenCV)",
       sc::run_match},
  };
  return table;
}

void print_usage(std::ostream& os) {
  os << "usage: sonarsynth <command> [options]   (sonarsynth <command> --help for details)\n\n"
        "commands:\n";
  for (const auto& c : commands()) {
    os << "  " << c.name << std::string(12 - std::min<size_t>(11, std::strlen(c.name)), ' ')
       << c.summary << "\n";
  }
}

}  // namespace

namespace sonarsynth::cli {
int run_version(const std::vector<std::string>& /*args*/) {
  try {
    sonarsynth::simd::configure_from_environment();
  } catch (const sonarsynth::Error& e) {
    std::cerr << "sonarsynth --version: error: " << e.what() << "\n";
    return 1;
  }
  std::cout << "sonarsynth " << sonarsynth::kVersion << "\n";
  // The instruction set the vector kernels run (SONARSYNTH_SIMD caps it; docs/benchmarks.md).
  std::cout << "vector kernels: "
            << sonarsynth::simd::target_name(sonarsynth::simd::active_target()) << "\n";
  return 0;
}
}  // namespace sonarsynth::cli

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  // glibc gives a block above its mmap threshold a mapping of its own, unmapped when freed; but
  // the threshold follows the largest such block freed (up to 32 MiB, and the heap's trim
  // threshold twice that), after which the multi-megabyte buffers of GDAL's overview
  // computations at the end of `simulate` come from the heap and stay resident once freed
  // (~15 MB on the paper scene). Fixed thresholds instead: every block of 1 MiB or more is
  // unmapped when freed (a few hundred a run, none per ping), and a heap keeps at most 8 MiB
  // free at its top (the 128 KiB default would return and fault in again the per-ping
  // buffers). docs/benchmarks.md, "Memory at the end of the run".
  ::mallopt(M_MMAP_THRESHOLD, 1 << 20);
  ::mallopt(M_TRIM_THRESHOLD, 8 << 20);
#endif
  sc::install_interrupt_cleanup();
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0) {
    print_usage(argc < 2 ? std::cerr : std::cout);
    return argc < 2 ? 2 : 0;
  }
  if (std::strcmp(argv[1], "--version") == 0) return sc::run_version({});
  const std::string name = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  for (const auto& c : commands()) {
    if (name != c.name) continue;
    try {
      return c.run(args);
    } catch (const boost::program_options::error& e) {
      std::cerr << "sonarsynth " << name << ": " << e.what() << "\n(see sonarsynth " << name
                << " --help)\n";
      return 2;
    } catch (const sonarsynth::Error& e) {
      std::cerr << "sonarsynth " << name << ": error: " << e.what() << "\n";
      return 1;
    } catch (const std::filesystem::filesystem_error& e) {
      // A path the user gave that the system refuses (name too long, permission denied, ...).
      std::cerr << "sonarsynth " << name << ": error: " << e.code().message() << ": "
                << e.path1().string() << (e.path2().empty() ? "" : " -> " + e.path2().string())
                << "\n";
      return 1;
    } catch (const std::system_error& e) {
      // std::thread / std::async refused by the system: a limit of the user's, not a bug.
      if (e.code() == std::errc::resource_unavailable_try_again) {
        std::cerr << "sonarsynth " << name
                  << ": error: could not start a thread: " << e.code().message()
                  << " (the limit on threads, ulimit -u, or on address space, ulimit -v, is "
                     "reached; raise it, or lower --threads where the command has it)\n";
        return 1;
      }
      std::cerr << "sonarsynth " << name << ": internal error: " << e.what() << "\n";
      return 3;
    } catch (const std::exception& e) {
      std::cerr << "sonarsynth " << name << ": internal error: " << e.what() << "\n";
      return 3;
    }
  }
  std::cerr << "sonarsynth: unknown command '" << name << "'\n";
  print_usage(std::cerr);
  return 2;
}
