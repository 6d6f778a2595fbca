// SPDX-License-Identifier: MIT
// `sonarsynth simulate` never destroys a user's files (-o ., -o .., a directory holding the scene
// or foreign files), validates --threads, and leaves no partial output after SIGINT/SIGTERM; the
// temporaries of a kill -9 are removed by the next run.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include "cli_test_util.hpp"
#include "scene_test_util.hpp"

extern char** environ;

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

// A quick scene: flat generated seabed, one 40 m line.
const std::string kQuickScene = test::flat_scene("quick", 3, 100, 100, 20, 2.0, 8) + R"(
    - {name: L1, waypoints: [{lat_deg: 43.0, lon_deg: 4.99975}, {lat_deg: 43.0, lon_deg: 5.00025}]}
sonar: {frequency_khz: 600, range_m: 25, samples: 256}
)";

// A slow one (thousands of 4096-sample pings on one thread) to interrupt while it renders.
const std::string kSlowScene = test::flat_scene("slow", 3, 400, 120, 20, 0.5, 8) + R"(
    - {name: L1, waypoints: [{lat_deg: 43.0, lon_deg: 4.9983}, {lat_deg: 43.0, lon_deg: 4.9985}]}
    - {name: L2, waypoints: [{lat_deg: 43.0, lon_deg: 4.9983}, {lat_deg: 43.0, lon_deg: 5.0017}]}
sonar: {frequency_khz: 600, range_m: 50, samples: 4096}
)";

using test::read_text;
using test::snapshot;

class OutputSafetyCli : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = test::scratch_path();
    fs::remove_all(root_);
    fs::create_directories(root_ / "work" / "sub");
    std::ofstream(root_ / "work" / "scene.yaml") << kQuickScene;
    std::ofstream(root_ / "work" / "keep.txt") << "precious";
    std::ofstream(root_ / "work" / "sub" / "data.bin") << "precious too";
  }
  void TearDown() override {
    fs::remove_all(root_);
    fs::remove_all(root_.string() + "_io");
  }

  /// Runs `sonarsynth <args>` with working directory `cwd`; stdout and stderr are captured in a
  /// directory beside root_, so that snapshots of root_ see only what the CLI did.
  test::CliResult cli(const fs::path& cwd, const std::string& args) {
    const fs::path io = root_.string() + "_io";
    fs::create_directories(io);
    const std::string cmd = "cd '" + cwd.string() + "' && " + SONARSYNTH_CLI + " " + args + " >'" +
                            (io / "out").string() + "' 2>'" + (io / "err").string() +
                            "' </dev/null";
    const int status = std::system(cmd.c_str());
    test::CliResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read_text(io / "out");
    r.err = read_text(io / "err");
    return r;
  }
  /// Runs `args` in `cwd` and expects it refused: exit status 1, `reason` in the message, nothing
  /// under root_ changed. Returns the result for further checks.
  test::CliResult refused(const fs::path& cwd, const std::string& args, const std::string& reason) {
    const auto before = snapshot(root_);
    test::CliResult r = cli(cwd, args);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(reason), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(snapshot(root_), before) << args;
    return r;
  }
  fs::path root_;
};

TEST_F(OutputSafetyCli, OverwriteOfTheWorkingDirectoryOrItsParentIsRefusedAndNothingChanges) {
  for (const char* out : {".", "..", "./", "sub/.."}) {
    refused(root_ / "work", std::string("simulate scene.yaml -q --overwrite -o ") + out,
            "working directory");
  }
}

TEST_F(OutputSafetyCli, ADirectoryHoldingTheSceneOrForeignFilesIsNeverReplaced) {
  // From elsewhere: the scene's own directory.
  refused(root_, "simulate work/scene.yaml -q --overwrite -o work", "contains the input");
  // A directory of someone else's files.
  refused(root_ / "work", "simulate scene.yaml -q --overwrite -o sub", "data.bin");
}

TEST_F(OutputSafetyCli, OverwriteReplacesAnEarlierOutputAndReRunsOfEffectiveYamlAreRefusedInPlace) {
  const fs::path work = root_ / "work";
  test::CliResult r = cli(work, "simulate scene.yaml -q --no-mosaic -o out");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string first_xtf = read_text(work / "out" / "L1.xtf");
  ASSERT_FALSE(first_xtf.empty());
  r = cli(work, "simulate scene.yaml -q --no-mosaic --seed 9 --overwrite -o out");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(read_text(work / "out" / "L1.xtf"), first_xtf) << "the new seed's results";
  // Only the results and the inputs: no hidden temporaries left next to them.
  for (const auto& e : fs::directory_iterator(work)) {
    EXPECT_NE(e.path().filename().string()[0], '.') << e.path();
  }
  // Re-running the effective configuration into its own directory would delete it.
  refused(work, "simulate out/effective.yaml -q --overwrite -o out", "contains the input");
}

TEST_F(OutputSafetyCli, OverwriteRefusesAUserDirectoryOfProductNamedFilesWithoutMarker) {
  const fs::path work = root_ / "work";
  fs::create_directory(work / "mine");
  std::ofstream(work / "mine" / "L1.xtf") << "my own copy";
  std::ofstream(work / "mine" / "effective.yaml") << "seed: 1\n";
  const test::CliResult r = refused(work, "simulate scene.yaml -q --no-mosaic --overwrite -o mine",
                                    "mine: refusing to use as the output directory");
  EXPECT_NE(r.err.find(".sonarsynth-output"), std::string::npos) << r.err;
}

TEST_F(OutputSafetyCli, AProductIsNeverWrittenOverItsInput) {
  const fs::path work = root_ / "work";
  ASSERT_EQ(cli(work, "simulate scene.yaml -q --no-mosaic -o out").exit_code, 0);
  for (const char* cmd : {"waterfall out/L1.xtf -q --overwrite -o out/L1.xtf",
                          "waterfall out/L1.xtf -q --overwrite -o ./out/../out/L1.xtf",
                          "mosaic out/L1.xtf -q --overwrite -o out/L1.xtf",
                          "mosaic out/L1.xtf -q --overwrite -o m.tif --rgb out/L1.xtf"}) {
    refused(work, cmd, "is the input");
  }
}

TEST_F(OutputSafetyCli, APathTheSystemRefusesIsANamedErrorNotAnInternalOne) {
  const fs::path golden = fs::path(SONARSYNTH_TEST_DATA_DIR) / "xtf" / "golden-tiny.xtf";
  const std::string long_name = std::string(300, 'w') + ".png";
  const test::CliResult r = refused(
      root_ / "work", "waterfall " + golden.string() + " -q -o " + long_name, "File name too long");
  EXPECT_NE(r.err.find(long_name), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
}

TEST_F(OutputSafetyCli, ThreadCountIsValidated) {
  const fs::path work = root_ / "work";
  for (const char* bad : {"-1", "0", "100000", "4294967295"}) {
    const test::CliResult r =
        refused(work, std::string("simulate scene.yaml -q -o out --threads ") + bad,
                "--threads = " + std::string(bad));
    EXPECT_NE(r.err.find("Violated constraint"), std::string::npos) << r.err;
  }
  refused(work, "bathy -o g.tif --lat 43 --lon 5 --size 10x10 --cell 1 --threads -1",
          "--threads = -1");
}

/// Starts `sonarsynth <args...>` in `cwd` without waiting; output to /dev/null.
pid_t spawn_cli(const fs::path& cwd, std::vector<std::string> args) {
  args.insert(args.begin(), SONARSYNTH_CLI);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addchdir_np(&fa, cwd.c_str());
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  return rc == 0 ? pid : -1;
}

/// Waits (up to 60 s) until `dir` holds `path`; false if it never appears.
bool wait_for(const fs::path& path) {
  for (int i = 0; i < 12000; ++i) {
    if (fs::exists(path)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

int exit_status(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1000 + WTERMSIG(status);
}

TEST_F(OutputSafetyCli, InterruptRemovesThePartialOutput) {
  const fs::path work = root_ / "work";
  std::ofstream(work / "slow.yaml") << kSlowScene;
  for (const int sig : {SIGINT, SIGTERM}) {
    const auto before = snapshot(root_);
    const pid_t pid =
        spawn_cli(work, {"simulate", "slow.yaml", "-q", "--threads", "1", "-o", "out"});
    ASSERT_GT(pid, 0);
    const fs::path part = work / (".out.part-" + std::to_string(pid));
    // SIGINT as soon as the output directory exists, SIGTERM once the renderer is writing (the
    // short first line is complete, the long second one under way).
    const char* wait_name = sig == SIGINT ? ".sonarsynth-output" : "L1.xtf";
    ASSERT_TRUE(wait_for(part / wait_name)) << "the run never got that far";
    ::kill(pid, sig);
    EXPECT_EQ(exit_status(pid), 128 + sig) << "signal " << sig << " ended the run normally";
    EXPECT_EQ(snapshot(root_), before) << "signal " << sig;
  }
}

TEST_F(OutputSafetyCli, AKilledRunsTemporariesAreRemovedByTheNextRun) {
  const fs::path work = root_ / "work";
  std::ofstream(work / "slow.yaml") << kSlowScene;
  const pid_t pid = spawn_cli(work, {"simulate", "slow.yaml", "-q", "--threads", "1", "-o", "out"});
  ASSERT_GT(pid, 0);
  const fs::path part = work / (".out.part-" + std::to_string(pid));
  ASSERT_TRUE(wait_for(part / ".sonarsynth-output"));
  ::kill(pid, SIGKILL);
  EXPECT_EQ(exit_status(pid), 1000 + SIGKILL);
  EXPECT_TRUE(fs::exists(part)) << "kill -9 cannot clean up; the next run must";
  const test::CliResult r = cli(work, "simulate scene.yaml -q --no-mosaic -o out");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(part));
  EXPECT_TRUE(fs::exists(work / "out" / "L1.xtf"));
}

}  // namespace
}  // namespace sonarsynth
