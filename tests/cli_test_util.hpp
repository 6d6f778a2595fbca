// SPDX-License-Identifier: MIT
// Running the `sonarsynth` CLI from tests.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace sonarsynth::test {

struct CliResult {
  int exit_code = -1;
  std::string out;  ///< stdout
  std::string err;  ///< stderr
};

/// Runs `sonarsynth <args>` (SONARSYNTH_CLI) through the shell, capturing stdout and stderr in
/// files under `scratch_dir`.
inline CliResult run_cli(const std::string& args, const std::filesystem::path& scratch_dir) {
  const auto out_file = scratch_dir / ".cli_stdout.txt";
  const auto err_file = scratch_dir / ".cli_stderr.txt";
  const std::string cmd = std::string(SONARSYNTH_CLI) + " " + args + " >" + out_file.string() +
                          " 2>" + err_file.string() + " </dev/null";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  r.out = slurp(out_file);
  r.err = slurp(err_file);
  std::filesystem::remove(out_file);
  std::filesystem::remove(err_file);
  return r;
}

}  // namespace sonarsynth::test
