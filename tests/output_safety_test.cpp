// SPDX-License-Identifier: MIT
// OutputDirectory and AtomicOutput never destroy what they did not write: refusals leave the disk
// unchanged, replacement swaps complete directories, temporaries of dead processes are cleaned.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "cli_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/atomic_file.hpp"
#include "sonarsynth/formats/registry/output_dir.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

using test::read_text;
using test::snapshot;

/// The id of a process that has ended.
long dead_pid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

class OutputSafety : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = test::scratch_path();
    fs::remove_all(root_);
    fs::create_directories(root_ / "work");
    write_text(root_ / "work" / "scene.yaml", "name: mine\n");
    saved_cwd_ = fs::current_path();
  }
  void TearDown() override {
    fs::current_path(saved_cwd_);
    fs::remove_all(root_);
  }
  /// Expects FormatError whose message contains `needle`, and an unchanged disk.
  void expect_refused(const fs::path& dir, bool overwrite, const std::vector<fs::path>& inputs,
                      const std::string& needle) {
    const auto before = snapshot(root_);
    try {
      OutputDirectory out(dir, overwrite, inputs);
      ADD_FAILURE() << dir << " accepted";
    } catch (const FormatError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
    EXPECT_EQ(snapshot(root_), before);
  }
  fs::path root_, saved_cwd_;
};

TEST_F(OutputSafety, RefusesTheWorkingDirectoryAndItsAncestors) {
  fs::current_path(root_ / "work");
  expect_refused(".", true, {}, "working directory");
  expect_refused("./", true, {}, "working directory");
  expect_refused("..", true, {}, "working directory");
  expect_refused(root_, true, {}, "working directory");
  expect_refused("/", true, {}, "root");
}

TEST_F(OutputSafety, RefusesADirectoryHoldingAnInput) {
  const fs::path work = root_ / "work";
  write_text(work / OutputDirectory::kMarkerName, "");  // even one that looks like ours
  expect_refused(work, true, {work / "scene.yaml"}, "contains the input");
  expect_refused(root_, true, {work / "scene.yaml"}, "contains the input");
}

TEST_F(OutputSafety, RefusesAnExistingDirectoryThatIsNotASonarsynthOutput) {
  const fs::path notes = root_ / "notes";
  fs::create_directory(notes);
  write_text(notes / "thesis.txt", "years of work");
  expect_refused(notes, true, {}, "thesis.txt");
  // Our marker does not license deleting a file someone added.
  write_text(notes / OutputDirectory::kMarkerName, "");
  expect_refused(notes, true, {}, "thesis.txt");
  // Without --overwrite, any existing directory is refused.
  fs::create_directory(root_ / "empty");
  expect_refused(root_ / "empty", false, {}, "already exists");
  // A file of that name is not a directory to replace.
  write_text(root_ / "file", "x");
  expect_refused(root_ / "file", true, {}, "not a directory");
}

TEST_F(OutputSafety, ReplacesAnOutputByASwapAndLeavesNoTemporaries) {
  const fs::path out_dir = root_ / "out";
  {
    OutputDirectory first(out_dir, false);
    write_text(first.file("a.xtf"), "old");
    first.commit();
  }
  EXPECT_TRUE(fs::exists(out_dir / OutputDirectory::kMarkerName));
  EXPECT_EQ(why_not_replaceable_output(out_dir), "");
  {
    OutputDirectory second(out_dir, true);
    write_text(second.file("b.xtf"), "new");
    // Until commit the old results stay in place, complete.
    EXPECT_EQ(read_text(out_dir / "a.xtf"), "old");
    second.commit();
  }
  EXPECT_FALSE(fs::exists(out_dir / "a.xtf"));
  EXPECT_EQ(read_text(out_dir / "b.xtf"), "new");
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(root_)) names.push_back(e.path().filename());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"out", "work"}));
}

TEST_F(OutputSafety, RefusesProductNamedFilesWithoutMarker) {
  // A user's directory holding only files with product names (copies of results, say) is not
  // ours without the marker: --overwrite must not replace it.
  const fs::path out_dir = root_ / "user_dir";
  fs::create_directory(out_dir);
  write_text(out_dir / "effective.yaml", "seed: 1\n");
  write_text(out_dir / "L1.xtf", "x");
  EXPECT_NE(why_not_replaceable_output(out_dir).find(".sonarsynth-output"), std::string::npos);
  expect_refused(out_dir, true, {}, ".sonarsynth-output");
  EXPECT_EQ(read_text(out_dir / "L1.xtf"), "x");
  EXPECT_EQ(read_text(out_dir / "effective.yaml"), "seed: 1\n");
  // With the marker it is ours again.
  write_text(out_dir / OutputDirectory::kMarkerName, "");
  EXPECT_EQ(why_not_replaceable_output(out_dir), "");
  OutputDirectory out(out_dir, true);
  out.commit();
  EXPECT_FALSE(fs::exists(out_dir / "L1.xtf"));
}

TEST_F(OutputSafety, DestroyedWithoutCommitLeavesNothing) {
  const auto before = snapshot(root_);
  {
    OutputDirectory out(root_ / "out", false);
    write_text(out.file("a.xtf"), "partial");
    EXPECT_TRUE(fs::exists(out.temp_dir()));
  }
  EXPECT_EQ(snapshot(root_), before);
}

TEST_F(OutputSafety, PendingTemporariesAreRemovedOnRequest) {
  OutputDirectory out(root_ / "out", false);
  AtomicOutput file(root_ / "grid.tif");
  write_text(out.file("a.xtf"), "partial");
  write_text(file.temp_path(), "partial");
  remove_pending_temporaries();  // what the CLI's SIGINT handler does
  EXPECT_FALSE(fs::exists(out.temp_dir()));
  EXPECT_FALSE(fs::exists(file.temp_path()));
  EXPECT_FALSE(fs::exists(root_ / "out"));
}

TEST_F(OutputSafety, StaleTemporariesOfDeadProcessesAreCleaned) {
  const long dead = dead_pid();
  const long alive = static_cast<long>(::getppid());
  // A killed run's partial directory, and a foreign directory with a matching name.
  const fs::path stale = root_ / (".out.part-" + std::to_string(dead));
  fs::create_directory(stale);
  write_text(stale / OutputDirectory::kMarkerName, "");
  write_text(stale / "a.xtf", "partial");
  const fs::path foreign = root_ / (".out.part-" + std::to_string(dead + 1000000));
  fs::create_directory(foreign);
  write_text(foreign / "keep.txt", "not ours");
  const fs::path running = root_ / (".out.part-" + std::to_string(alive));
  fs::create_directory(running);
  write_text(running / OutputDirectory::kMarkerName, "");
  // Old results set aside by a run killed between the two renames of the fallback swap.
  const fs::path aside = root_ / (".out.old-" + std::to_string(dead));
  fs::create_directory(aside);
  write_text(aside / OutputDirectory::kMarkerName, "");
  write_text(aside / "old.xtf", "complete");
  // A killed `bathy` run's partial file, and a live one.
  const fs::path stale_file = root_ / (".grid.part-" + std::to_string(dead) + "-3.tif");
  const fs::path live_file = root_ / (".grid.part-" + std::to_string(alive) + "-0.tif");
  write_text(stale_file, "partial");
  write_text(live_file, "partial");
  // Their helper files (the mosaic's overview levels are written beside its temporary).
  const fs::path stale_helper = stale_file.string() + ".levels.tif";
  const fs::path live_helper = live_file.string() + ".levels.tif";
  write_text(stale_helper, "partial");
  write_text(live_helper, "partial");
  // Not helpers: another stem's, and a name with text between the temporary's and the dot.
  const fs::path other_helper =
      root_ / (".grids.part-" + std::to_string(dead) + "-3.tif.levels.tif");
  const fs::path not_helper = root_ / (".grid.part-" + std::to_string(dead) + "-3x.tif.levels.tif");
  write_text(other_helper, "not ours");
  write_text(not_helper, "not ours");

  {
    OutputDirectory out(root_ / "other", false);
    EXPECT_TRUE(fs::exists(stale)) << "only temporaries of the same name are touched";
  }
  {
    OutputDirectory out(root_ / "out", true);
    EXPECT_FALSE(fs::exists(stale));
    EXPECT_TRUE(fs::exists(foreign / "keep.txt"));
    EXPECT_TRUE(fs::exists(running));
    EXPECT_FALSE(fs::exists(aside));
    EXPECT_EQ(read_text(root_ / "out" / "old.xtf"), "complete") << "set-aside results restored";
  }
  {
    AtomicOutput grid(root_ / "grid.tif");
    EXPECT_FALSE(fs::exists(stale_file));
    EXPECT_TRUE(fs::exists(live_file));
    EXPECT_FALSE(fs::exists(stale_helper));
    EXPECT_TRUE(fs::exists(live_helper));
    EXPECT_TRUE(fs::exists(other_helper));
    EXPECT_TRUE(fs::exists(not_helper));
  }
}

TEST(TemporaryNames, OwnerPidParsedOnlyFromExactNames) {
  EXPECT_EQ(temporary_owner_pid(".out.part-123", ".out.part-", ""), 123);
  EXPECT_EQ(temporary_owner_pid(".g.part-77-4.tif", ".g.part-", ".tif"), 77);
  EXPECT_EQ(temporary_owner_pid(".out.part-12x", ".out.part-", ""), -1);
  EXPECT_EQ(temporary_owner_pid(".out.part-", ".out.part-", ""), -1);
  EXPECT_EQ(temporary_owner_pid(".outer.part-5", ".out.part-", ""), -1);
  EXPECT_EQ(temporary_owner_pid(".g.part-77-4.png", ".g.part-", ".tif"), -1);
}

TEST(AtomicOutputSafety, RefusesADirectoryAsTheFile) {
  const fs::path dir = fs::temp_directory_path() / ("sonarsynth_ao_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  EXPECT_THROW(AtomicOutput(dir, true), FormatError);
  EXPECT_TRUE(fs::is_directory(dir));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth
