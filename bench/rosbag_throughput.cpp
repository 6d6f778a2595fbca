// SPDX-License-Identifier: MIT
// ROS 1 bag write and read throughput against XTF's, alternating in one run (docs/rosbag.md,
// "Throughput"): the same pings (2 x 4096 u16 samples) written with rosbag::Writer and
// xtf::Writer, then read back as pings with rosbag::Reader and xtf::Reader (page cache); medians
// of several runs, MB/s of each file and the bag/XTF time ratios.
// Usage: rosbag_throughput [pings=10000] [samples=4096] [runs=5] [directory=temp]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "sonarsynth/formats/rosbag/reader.hpp"
#include "sonarsynth/formats/rosbag/writer.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "throughput_ping.hpp"

namespace fs = std::filesystem;
using bench::median;
using Clock = std::chrono::steady_clock;

namespace {

template <class W, class Options>
double write_seconds(const fs::path& path, Options options, sonarsynth::SonarPing& ping,
                     std::uint32_t pings, std::uint64_t& bytes) {
  const auto t0 = sonarsynth::UtcTime{std::chrono::sys_days{std::chrono::year{2024} / 1 / 1}};
  options.overwrite = true;
  const auto start = Clock::now();
  W w(path, options);
  for (std::uint32_t k = 0; k < pings; ++k) {
    ping.ping_number = k;
    ping.time_utc = t0 + std::chrono::milliseconds(100) * k;
    w.write_ping(ping);
  }
  w.close();
  const double s = std::chrono::duration<double>(Clock::now() - start).count();
  bytes = fs::file_size(path);
  return s;
}

/// Seconds to read every ping of `path`; `pings` counts them (the sample sum keeps the work).
template <class Next>
double read_seconds(Next&& read_all, std::uint64_t& pings) {
  const auto start = Clock::now();
  pings = read_all();
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::uint64_t read_bag(const fs::path& path) {
  sonarsynth::rosbag::Reader r(path);
  sonarsynth::rosbag::Ping p;
  std::uint64_t n = 0;
  while (r.next_ping(p)) n += p.sonar.port.size() > 0 ? 1u : 0u;
  return n;
}

std::uint64_t read_xtf(const fs::path& path) {
  sonarsynth::xtf::Reader r(path);
  sonarsynth::xtf::Packet p;
  std::uint64_t n = 0;
  while (r.next(p)) n += p.kind == sonarsynth::xtf::PacketKind::kPing ? 1u : 0u;
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  const std::uint32_t pings = argc > 1 ? static_cast<std::uint32_t>(std::atoi(argv[1])) : 10000;
  const std::size_t samples = argc > 2 ? static_cast<std::size_t>(std::atoi(argv[2])) : 4096;
  const int runs = argc > 3 ? std::atoi(argv[3]) : 5;
  const fs::path dir = argc > 4 ? fs::path(argv[4]) : fs::temp_directory_path();

  sonarsynth::SonarPing ping = bench::throughput_ping(samples);
  std::vector<double> bag_s, xtf_s, ratio;
  std::uint64_t bag_bytes = 0, xtf_bytes = 0;
  for (int run = 0; run < runs; ++run) {
    bag_s.push_back(write_seconds<sonarsynth::rosbag::Writer>(
        dir / "sonarsynth_rosbag_throughput.bag", sonarsynth::rosbag::WriterOptions{}, ping, pings,
        bag_bytes));
    xtf_s.push_back(write_seconds<sonarsynth::xtf::Writer>(dir / "sonarsynth_rosbag_throughput.xtf",
                                                           sonarsynth::xtf::WriterOptions{}, ping,
                                                           pings, xtf_bytes));
    ratio.push_back(bag_s.back() / xtf_s.back());
  }
  // Reading: both files as written by the last run, alternating.
  std::vector<double> bag_r, xtf_r, read_ratio;
  for (int run = 0; run < runs; ++run) {
    std::uint64_t bag_pings = 0, xtf_pings = 0;
    bag_r.push_back(read_seconds([&] { return read_bag(dir / "sonarsynth_rosbag_throughput.bag"); },
                                 bag_pings));
    xtf_r.push_back(read_seconds([&] { return read_xtf(dir / "sonarsynth_rosbag_throughput.xtf"); },
                                 xtf_pings));
    read_ratio.push_back(bag_r.back() / xtf_r.back());
    if (bag_pings != pings || xtf_pings != pings) {
      std::fprintf(stderr, "read %llu bag and %llu XTF pings of %u\n",
                   static_cast<unsigned long long>(bag_pings),
                   static_cast<unsigned long long>(xtf_pings), pings);
      return 1;
    }
  }
  fs::remove(dir / "sonarsynth_rosbag_throughput.bag");
  fs::remove(dir / "sonarsynth_rosbag_throughput.xtf");
  const double bag_mb = static_cast<double>(bag_bytes) / 1e6;
  const double xtf_mb = static_cast<double>(xtf_bytes) / 1e6;
  std::printf("pings %u, samples %zu, runs %d\n", pings, samples, runs);
  std::printf("bag write: %.1f MB in %.3f s median: %.0f MB/s\n", bag_mb, median(bag_s),
              bag_mb / median(bag_s));
  std::printf("xtf write: %.1f MB in %.3f s median: %.0f MB/s\n", xtf_mb, median(xtf_s),
              xtf_mb / median(xtf_s));
  std::printf("bag/xtf time ratio (median of per-run ratios): %.2f\n", median(ratio));
  std::printf("bag read: %.3f s median: %.0f MB/s\n", median(bag_r), bag_mb / median(bag_r));
  std::printf("xtf read: %.3f s median: %.0f MB/s\n", median(xtf_r), xtf_mb / median(xtf_r));
  std::printf("bag/xtf read time ratio (median of per-run ratios): %.2f\n", median(read_ratio));
  return 0;
}
