// SPDX-License-Identifier: MIT
#include "cli_util.hpp"

#include <charconv>
#include <filesystem>
#include <iostream>

#include "sonarsynth/error.hpp"

namespace sonarsynth::cli {

void add_overwrite_quiet_options(po::options_description& options) {
  options.add_options()("overwrite", "replace an existing output file")("quiet,q",
                                                                        "print nothing on success");
}

po::positional_options_description one_input() {
  po::positional_options_description positional;
  positional.add("input", 1);
  return positional;
}

void warn_reader_anomalies(const char* command, std::uint64_t count,
                           const std::vector<std::string>& messages) {
  if (count == 0) return;
  std::cerr << "sonarsynth " << command << ": warning: " << count
            << " anomalies while reading (malformed packets skipped; see sonarsynth info):\n";
  for (const std::string& m : messages) std::cerr << "  " << m << "\n";
  if (messages.size() < count) std::cerr << "  ... (" << count - messages.size() << " more)\n";
}

bool parse(const std::vector<std::string>& args, const po::options_description& options,
           const po::positional_options_description& positional, po::variables_map& vm,
           const std::string& usage) {
  po::options_description all = options;
  all.add_options()("help,h", "show this help and exit");
  po::store(po::command_line_parser(args).options(all).positional(positional).run(), vm);
  if (vm.count("help")) {
    std::cout << usage << "\n\n" << all << "\n";
    return false;
  }
  po::notify(vm);
  return true;
}

std::vector<std::pair<std::string, std::string>> parse_key_values(
    const std::vector<std::string>& items, const char* option_name) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const std::string& item : items) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw InputError(std::string("--") + option_name + " = '" + item +
                       "'. Violated constraint: KEY=VALUE");
    }
    out.emplace_back(item.substr(0, eq), item.substr(eq + 1));
  }
  return out;
}

std::uint64_t parse_uint64(const std::string& text, const char* option_name) {
  std::uint64_t v = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || ptr != end) {
    throw InputError(std::string("--") + option_name + " = '" + text +
                     "'. Violated constraint: an integer from 0 to 18446744073709551615");
  }
  return v;
}

}  // namespace sonarsynth::cli

#include <unistd.h>

#include <chrono>
#include <cstdio>

namespace sonarsynth::cli {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

ProgressBar::ProgressBar(bool quiet, std::string unit)
    : enabled_(!quiet && ::isatty(STDERR_FILENO)), unit_(std::move(unit)), start_s_(now_s()) {}

void ProgressBar::update(std::uint64_t done, std::uint64_t total) {
  if (!enabled_ || total == 0) return;
  const double t = now_s();
  if (done < total && t - last_draw_s_ < 0.1) return;
  last_draw_s_ = t;
  const double elapsed = t - start_s_;
  const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
  const double left = rate > 0 ? static_cast<double>(total - done) / rate : 0.0;
  const int width = 30;
  const int filled =
      static_cast<int>(width * static_cast<double>(done) / static_cast<double>(total));
  std::fprintf(stderr, "\r[%s%s] %llu/%llu %s  %.0f %s/s  %.0f s left ",
               std::string(static_cast<std::size_t>(filled), '#').c_str(),
               std::string(static_cast<std::size_t>(width - filled), ' ').c_str(),
               static_cast<unsigned long long>(done), static_cast<unsigned long long>(total),
               unit_.c_str(), rate, unit_.c_str(), left);
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (enabled_) std::fprintf(stderr, "\n");
}

}  // namespace sonarsynth::cli

namespace sonarsynth::cli {

unsigned checked_thread_count(long long value, long long min_value) {
  if (value < min_value || value > kMaxThreadsOption) {
    throw InputError("--threads = " + std::to_string(value) +
                     ". Violated constraint: " + std::to_string(min_value) +
                     " <= threads <= " + std::to_string(kMaxThreadsOption));
  }
  return static_cast<unsigned>(value);
}

}  // namespace sonarsynth::cli
