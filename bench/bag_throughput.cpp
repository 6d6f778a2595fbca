// SPDX-License-Identifier: MIT
// Bag write and read throughput against XTF's, alternating in one run (docs/rosbag.md and
// docs/robotics.md, "Throughput"): the same pings (2 x 4096 u16 samples, noise-like so that the
// MCAP writer's zstd cannot shrink them to nothing) written as a ROS 1 bag or an MCAP file and
// as XTF, then read back as pings (page cache); medians of several runs, MB/s of each file and
// of the samples, and the bag/XTF time ratios.
// Usage: bag_throughput rosbag|mcap [pings=10000] [samples=4096] [runs=5] [directory=temp]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "sonarsynth/formats/mcap/reader.hpp"
#include "sonarsynth/formats/mcap/writer.hpp"
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
double write_seconds(const fs::path& path, Options options,
                     std::vector<sonarsynth::SonarPing>& pool, std::uint32_t pings,
                     std::uint64_t& bytes) {
  const auto t0 = sonarsynth::UtcTime{std::chrono::sys_days{std::chrono::year{2024} / 1 / 1}};
  options.overwrite = true;
  const auto start = Clock::now();
  W w(path, options);
  for (std::uint32_t k = 0; k < pings; ++k) {
    sonarsynth::SonarPing& ping = pool[k % pool.size()];
    ping.ping_number = k;
    ping.time_utc = t0 + std::chrono::milliseconds(100) * k;
    w.write_ping(ping);
  }
  w.close();
  const double s = std::chrono::duration<double>(Clock::now() - start).count();
  bytes = fs::file_size(path);
  return s;
}

/// Seconds to read every ping of `path` with `BagReader`; `pings` counts them.
template <class BagReader>
double read_bag_seconds(const fs::path& path, std::uint64_t& pings) {
  const auto start = Clock::now();
  BagReader r(path);
  sonarsynth::rosbag::Ping p;
  pings = 0;
  while (r.next_ping(p)) pings += p.sonar.port.size() > 0 ? 1u : 0u;
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double read_xtf_seconds(const fs::path& path, std::uint64_t& pings) {
  const auto start = Clock::now();
  sonarsynth::xtf::Reader r(path);
  sonarsynth::xtf::Packet p;
  pings = 0;
  while (r.next(p)) pings += p.kind == sonarsynth::xtf::PacketKind::kPing ? 1u : 0u;
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// 97 pings of `samples` noise-like samples per side (a hash of the index): 1.6 MB at 4096
/// samples, more than zstd level 1's window.
std::vector<sonarsynth::SonarPing> ping_pool(std::size_t samples) {
  const auto noise = [](std::uint64_t x) {
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return static_cast<float>((x ^ (x >> 31)) % 32768);
  };
  std::vector<sonarsynth::SonarPing> pool(97, bench::throughput_ping(samples));
  for (std::size_t k = 0; k < pool.size(); ++k) {
    for (std::size_t i = 0; i < samples; ++i) {
      pool[k].port[i] = noise(2 * k * samples + i);
      pool[k].starboard[i] = noise((2 * k + 1) * samples + i);
    }
  }
  return pool;
}

template <class BagWriter, class BagWriterOptions, class BagReader>
int run(std::string_view format, std::uint32_t pings, std::size_t samples, int runs,
        const fs::path& dir) {
  std::vector<sonarsynth::SonarPing> pool = ping_pool(samples);
  const fs::path bag = dir / ("sonarsynth_bag_throughput." + std::string(format));
  const fs::path xtf = dir / "sonarsynth_bag_throughput.xtf";
  std::vector<double> bag_s, xtf_s, ratio;
  std::uint64_t bag_bytes = 0, xtf_bytes = 0;
  for (int r = 0; r < runs; ++r) {
    bag_s.push_back(write_seconds<BagWriter>(bag, BagWriterOptions{}, pool, pings, bag_bytes));
    xtf_s.push_back(write_seconds<sonarsynth::xtf::Writer>(xtf, sonarsynth::xtf::WriterOptions{},
                                                           pool, pings, xtf_bytes));
    ratio.push_back(bag_s.back() / xtf_s.back());
  }
  // Reading: both files as written by the last run, alternating.
  std::vector<double> bag_r, xtf_r, read_ratio;
  for (int r = 0; r < runs; ++r) {
    std::uint64_t bag_pings = 0, xtf_pings = 0;
    bag_r.push_back(read_bag_seconds<BagReader>(bag, bag_pings));
    xtf_r.push_back(read_xtf_seconds(xtf, xtf_pings));
    read_ratio.push_back(bag_r.back() / xtf_r.back());
    if (bag_pings != pings || xtf_pings != pings) {
      std::fprintf(stderr, "read %llu %s and %llu XTF pings of %u\n",
                   static_cast<unsigned long long>(bag_pings), std::string(format).c_str(),
                   static_cast<unsigned long long>(xtf_pings), pings);
      return 1;
    }
  }
  fs::remove(bag);
  fs::remove(xtf);
  const double bag_mb = static_cast<double>(bag_bytes) / 1e6;
  const double xtf_mb = static_cast<double>(xtf_bytes) / 1e6;
  // The samples as the XTF holds them (u16): the payload both files carry.
  const double payload_mb = 4.0 * static_cast<double>(samples) * pings / 1e6;
  const char* f = format == "rosbag" ? "bag" : "mcap";
  std::printf("pings %u, samples %zu, runs %d, sample payload %.1f MB\n", pings, samples, runs,
              payload_mb);
  std::printf("%s write: %.1f MB in %.3f s median: %.0f MB/s of file, %.0f MB/s of samples\n", f,
              bag_mb, median(bag_s), bag_mb / median(bag_s), payload_mb / median(bag_s));
  std::printf("xtf write: %.1f MB in %.3f s median: %.0f MB/s\n", xtf_mb, median(xtf_s),
              xtf_mb / median(xtf_s));
  std::printf("%s/xtf time ratio (median of per-run ratios): %.2f\n", f, median(ratio));
  std::printf("%s read: %.3f s median: %.0f MB/s of file, %.0f MB/s of samples\n", f, median(bag_r),
              bag_mb / median(bag_r), payload_mb / median(bag_r));
  std::printf("xtf read: %.3f s median: %.0f MB/s\n", median(xtf_r), xtf_mb / median(xtf_r));
  std::printf("%s/xtf read time ratio (median of per-run ratios): %.2f\n", f, median(read_ratio));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string_view format = argc > 1 ? argv[1] : "";
  const std::uint32_t pings = argc > 2 ? static_cast<std::uint32_t>(std::atoi(argv[2])) : 10000;
  const std::size_t samples = argc > 3 ? static_cast<std::size_t>(std::atoi(argv[3])) : 4096;
  const int runs = argc > 4 ? std::atoi(argv[4]) : 5;
  const fs::path dir = argc > 5 ? fs::path(argv[5]) : fs::temp_directory_path();
  if (pings == 0 || samples == 0 || runs < 1) {
    std::fprintf(stderr, "bag_throughput: pings, samples and runs must be >= 1\n");
    return 2;
  }
  if (format == "rosbag") {
    return run<sonarsynth::rosbag::Writer, sonarsynth::rosbag::WriterOptions,
               sonarsynth::rosbag::Reader>(format, pings, samples, runs, dir);
  }
  if (format == "mcap") {
    return run<sonarsynth::mcap::Writer, sonarsynth::mcap::WriterOptions, sonarsynth::mcap::Reader>(
        format, pings, samples, runs, dir);
  }
  std::fprintf(stderr,
               "usage: bag_throughput rosbag|mcap [pings=10000] [samples=4096] [runs=5] "
               "[directory=temp]\n");
  return 2;
}
