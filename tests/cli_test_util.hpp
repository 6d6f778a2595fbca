// SPDX-License-Identifier: MIT
// Running the `sonarsynth` CLI from tests, and the scratch directories and file snapshots the
// CLI tests share.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
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

/// The bytes of the file `p` ("" if it cannot be read).
inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Every path under `root` (recursively, hidden ones included) with its content; "<dir>" for a
/// directory. Two snapshots compare equal when nothing under `root` changed.
inline std::map<std::string, std::string> snapshot(const std::filesystem::path& root) {
  std::map<std::string, std::string> out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(root)) {
    const std::string rel = std::filesystem::relative(e.path(), root).string();
    out[rel] = e.is_regular_file() ? read_text(e.path()) : std::string("<dir>");
  }
  return out;
}

/// An empty directory <tmp>/sonarsynth_<stem>_<pid> (removed first if it exists).
inline std::filesystem::path fresh_temp_dir(const std::string& stem) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("sonarsynth_" + stem + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// The scratch directory of the running test: <tmp>/sonarsynth_<suite>_<pid>_<test>. The process
/// id keeps apart two checkouts (or two runs) testing at the same time.
inline std::filesystem::path scratch_path() {
  const ::testing::TestInfo* t = ::testing::UnitTest::GetInstance()->current_test_info();
  return std::filesystem::temp_directory_path() /
         ("sonarsynth_" + std::string(t->test_suite_name()) + "_" + std::to_string(::getpid()) +
          "_" + t->name());
}

/// A fixture whose `dir_` is an empty scratch directory (scratch_path()) for each test, removed
/// afterwards; `write` puts a file in it.
class ScratchDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = scratch_path();
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  std::filesystem::path dir_;
};

}  // namespace sonarsynth::test
