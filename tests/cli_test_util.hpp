// SPDX-License-Identifier: MIT
// Running the `sonarsynth` CLI from tests.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

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
/// files under `scratch_dir`, named by process id and call so that tests running in parallel
/// (ctest -j) never share them.
inline CliResult run_cli(const std::string& args, const std::filesystem::path& scratch_dir) {
  static int calls = 0;
  const std::string tag = std::to_string(::getpid()) + "-" + std::to_string(calls++);
  const auto out_file = scratch_dir / (".cli_stdout-" + tag + ".txt");
  const auto err_file = scratch_dir / (".cli_stderr-" + tag + ".txt");
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
