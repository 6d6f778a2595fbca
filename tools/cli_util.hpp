// SPDX-License-Identifier: MIT
#pragma once

#include <boost/program_options.hpp>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace sonarsynth::cli {

namespace po = boost::program_options;

/// A subcommand: `sonarsynth <name> ...`. `run` gets the arguments after the name and returns the
/// process exit code. It may throw sonarsynth::Error (exit 1) or a program_options error (exit 2).
struct Command {
  const char* name;
  const char* summary;
  std::function<int(const std::vector<std::string>& args)> run;
};

/// Parses `args` against `options` (+ positional), handles --help by printing `usage` and the
/// options. Returns false if help was printed (the command should return 0).
bool parse(const std::vector<std::string>& args, const po::options_description& options,
           const po::positional_options_description& positional, po::variables_map& vm,
           const std::string& usage);

/// Adds --overwrite ("replace an existing output file") and --quiet/-q ("print nothing on
/// success"), the last options of the commands that write one file.
void add_overwrite_quiet_options(po::options_description& options);

/// The positional argument of the commands that read one file: the option "input".
po::positional_options_description one_input();

/// If `count` > 0, warns on stderr ("sonarsynth <command>: warning: N anomalies while reading
/// ...") with the `messages` kept and how many more there were.
void warn_reader_anomalies(const char* command, std::uint64_t count,
                           const std::vector<std::string>& messages);

/// Parses "KEY=VALUE" strings (GDAL's --co style); throws InputError naming the option otherwise.
std::vector<std::pair<std::string, std::string>> parse_key_values(
    const std::vector<std::string>& items, const char* option_name);

/// Parses an unsigned 64-bit option value (a seed) from its text; throws InputError naming
/// `--option_name` and the text for anything else ("-1", "1.5", "x"), which a number-typed option
/// would take silently ("-1" as 2^64 - 1).
std::uint64_t parse_uint64(const std::string& text, const char* option_name);

}  // namespace sonarsynth::cli

namespace sonarsynth::cli {

/// A one-line progress bar on stderr ("[####    ] 1200/9604 pings  950 pings/s  9 s left"),
/// drawn only when stderr is a terminal and not quiet.
class ProgressBar {
 public:
  ProgressBar(bool quiet, std::string unit);
  void update(std::uint64_t done, std::uint64_t total);
  void finish();

 private:
  bool enabled_;
  std::string unit_;
  double start_s_;
  double last_draw_s_ = -1.0;
};

/// Seconds since an arbitrary epoch (steady clock).
double now_s();

}  // namespace sonarsynth::cli

namespace sonarsynth::cli {

/// Largest --threads accepted; the renderers start at most four threads per core anyway.
inline constexpr long long kMaxThreadsOption = 1024;

/// Checks a --threads value read as a signed integer (so that "-1" is not read as 4294967295):
/// throws InputError "--threads = V. Violated constraint: ..." unless min_value <= V <= 1024.
unsigned checked_thread_count(long long value, long long min_value);

}  // namespace sonarsynth::cli
