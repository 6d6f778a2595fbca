// SPDX-License-Identifier: MIT
// ROS 2 bag (MCAP) write and read throughput against XTF's, alternating in one run
// (docs/robotics.md, "Throughput"): the same pings (2 x 4096 u16 samples) written with
// mcap::Writer and xtf::Writer, then read back as pings with mcap::Reader and xtf::Reader (page
// cache); medians of several runs, MB/s of each file and the MCAP/XTF time ratios.
// Usage: mcap_throughput [pings=10000] [samples=4096] [runs=5] [directory=temp]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "sonarsynth/formats/mcap/reader.hpp"
#include "sonarsynth/formats/mcap/writer.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

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

/// Seconds to read every ping of `path`; `pings` counts them (the sample sum keeps the work).
template <class Next>
double read_seconds(Next&& read_all, std::uint64_t& pings) {
  const auto start = Clock::now();
  pings = read_all();
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::uint64_t read_bag(const fs::path& path) {
  sonarsynth::mcap::Reader r(path);
  sonarsynth::mcap::Ping p;
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

  sonarsynth::SonarPing ping;
  ping.sensor_position = {sonarsynth::rad_from_deg(48.4), sonarsynth::rad_from_deg(-68.8), 0.0};
  ping.altitude_m = 10.0;
  ping.slant_range_m = 75.0;
  ping.port.resize(samples);
  ping.starboard.resize(samples);
  // Noise-like samples (a hash of the index), 97 different pings (1.6 MB, more than zstd level
  // 1's window): zstd cannot shrink them to nothing as it would repeated ones.
  const auto noise = [](std::uint64_t x) {
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return static_cast<float>((x ^ (x >> 31)) % 32768);
  };
  std::vector<sonarsynth::SonarPing> pool(97, ping);
  for (std::size_t k = 0; k < pool.size(); ++k) {
    for (std::size_t i = 0; i < samples; ++i) {
      pool[k].port[i] = noise(2 * k * samples + i);
      pool[k].starboard[i] = noise((2 * k + 1) * samples + i);
    }
  }
  std::vector<double> bag_s, xtf_s, ratio;
  std::uint64_t bag_bytes = 0, xtf_bytes = 0;
  for (int run = 0; run < runs; ++run) {
    bag_s.push_back(write_seconds<sonarsynth::mcap::Writer>(dir / "sonarsynth_mcap_throughput.mcap",
                                                            sonarsynth::mcap::WriterOptions{}, pool,
                                                            pings, bag_bytes));
    xtf_s.push_back(write_seconds<sonarsynth::xtf::Writer>(dir / "sonarsynth_mcap_throughput.xtf",
                                                           sonarsynth::xtf::WriterOptions{}, pool,
                                                           pings, xtf_bytes));
    ratio.push_back(bag_s.back() / xtf_s.back());
  }
  // Reading: both files as written by the last run, alternating.
  std::vector<double> bag_r, xtf_r, read_ratio;
  for (int run = 0; run < runs; ++run) {
    std::uint64_t bag_pings = 0, xtf_pings = 0;
    bag_r.push_back(
        read_seconds([&] { return read_bag(dir / "sonarsynth_mcap_throughput.mcap"); }, bag_pings));
    xtf_r.push_back(
        read_seconds([&] { return read_xtf(dir / "sonarsynth_mcap_throughput.xtf"); }, xtf_pings));
    read_ratio.push_back(bag_r.back() / xtf_r.back());
    if (bag_pings != pings || xtf_pings != pings) {
      std::fprintf(stderr, "read %llu MCAP and %llu XTF pings of %u\n",
                   static_cast<unsigned long long>(bag_pings),
                   static_cast<unsigned long long>(xtf_pings), pings);
      return 1;
    }
  }
  fs::remove(dir / "sonarsynth_mcap_throughput.mcap");
  fs::remove(dir / "sonarsynth_mcap_throughput.xtf");
  const double bag_mb = static_cast<double>(bag_bytes) / 1e6;
  const double xtf_mb = static_cast<double>(xtf_bytes) / 1e6;
  // The samples as the XTF holds them (u16): the payload both files carry.
  const double payload_mb = 4.0 * static_cast<double>(samples) * pings / 1e6;
  std::printf("pings %u, samples %zu, runs %d, sample payload %.1f MB\n", pings, samples, runs,
              payload_mb);
  std::printf("mcap write: %.1f MB in %.3f s median: %.0f MB/s of file, %.0f MB/s of samples\n",
              bag_mb, median(bag_s), bag_mb / median(bag_s), payload_mb / median(bag_s));
  std::printf("xtf write: %.1f MB in %.3f s median: %.0f MB/s\n", xtf_mb, median(xtf_s),
              xtf_mb / median(xtf_s));
  std::printf("mcap/xtf time ratio (median of per-run ratios): %.2f\n", median(ratio));
  std::printf("mcap read: %.3f s median: %.0f MB/s of file, %.0f MB/s of samples\n", median(bag_r),
              bag_mb / median(bag_r), payload_mb / median(bag_r));
  std::printf("xtf read: %.3f s median: %.0f MB/s\n", median(xtf_r), xtf_mb / median(xtf_r));
  std::printf("mcap/xtf read time ratio (median of per-run ratios): %.2f\n", median(read_ratio));
  return 0;
}
