// SPDX-License-Identifier: MIT
// XTF write and read throughput: a 10,000-ping file with 2 x 4096 u16 samples per ping, written
// with xtf::Writer and read back with xtf::Reader; median of several runs, MB/s and pings/s.
// Usage: xtf_throughput [pings=10000] [samples=4096] [runs=5] [directory=temp]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "throughput_ping.hpp"

namespace xtf = sonarsynth::xtf;
namespace fs = std::filesystem;
using bench::median;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
  const std::uint32_t pings = argc > 1 ? static_cast<std::uint32_t>(std::atoi(argv[1])) : 10000;
  const std::size_t samples = argc > 2 ? static_cast<std::size_t>(std::atoi(argv[2])) : 4096;
  const int runs = argc > 3 ? std::atoi(argv[3]) : 5;
  const fs::path dir = argc > 4 ? fs::path(argv[4]) : fs::temp_directory_path();
  const fs::path path = dir / "sonarsynth_xtf_throughput.xtf";

  sonarsynth::SonarPing ping = bench::throughput_ping(samples);
  const auto t0 = sonarsynth::UtcTime{std::chrono::sys_days{std::chrono::year{2024} / 1 / 1}};

  std::vector<double> write_s, read_s;
  std::uint64_t bytes = 0;
  for (int run = 0; run < runs; ++run) {
    xtf::WriterOptions options;
    options.overwrite = true;
    auto start = Clock::now();
    {
      xtf::Writer w(path, options);
      for (std::uint32_t k = 0; k < pings; ++k) {
        ping.ping_number = k;
        ping.time_utc = t0 + std::chrono::milliseconds(100) * k;
        w.write_ping(ping);
      }
      w.close();
      bytes = w.bytes_written();
    }
    write_s.push_back(std::chrono::duration<double>(Clock::now() - start).count());

    start = Clock::now();
    xtf::Reader r(path);
    xtf::Packet p;
    std::uint64_t n = 0;
    double checksum = 0.0;
    while (r.next(p)) {
      if (p.kind == xtf::PacketKind::kPing) {
        ++n;
        checksum += p.ping.sonar.starboard.back();
      }
    }
    read_s.push_back(std::chrono::duration<double>(Clock::now() - start).count());
    if (n != pings || r.total_anomalies() != 0 || checksum <= 0.0) {
      std::fprintf(stderr, "read back %llu pings, %llu anomalies\n",
                   static_cast<unsigned long long>(n),
                   static_cast<unsigned long long>(r.total_anomalies()));
      return 1;
    }
  }
  fs::remove(path);
  const double mb = static_cast<double>(bytes) / 1e6;
  const double w = median(write_s), rd = median(read_s);
  std::printf("file: %u pings x 2 x %zu u16 samples = %.1f MB; median of %d runs\n", pings, samples,
              mb, runs);
  std::printf("write: %.3f s  %.0f MB/s  %.0f pings/s\n", w, mb / w, pings / w);
  std::printf("read:  %.3f s  %.0f MB/s  %.0f pings/s\n", rd, mb / rd, pings / rd);
  return 0;
}
