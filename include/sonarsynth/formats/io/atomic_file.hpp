// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace sonarsynth {

/// A file that appears under its final name only when complete.
///
/// Write to temp_path() (a hidden name in the same directory, so the rename is atomic), then call
/// commit(). If the object is destroyed without commit() — an exception, a crash of the writer —
/// the temporary file is removed and nothing is left that looks like a complete output. While it
/// exists the temporary file is listed for remove_pending_temporaries() (the CLI calls that on
/// SIGINT/SIGTERM), and temporaries of the same name left by processes that no longer run (kill
/// -9, power loss) are removed when the next AtomicOutput for that name is created, with their
/// helper files: a writer that needs a scratch file beside the temporary names it
/// temp_path() + ".<suffix>" (the mosaic's overview levels: ".levels.tif").
class AtomicOutput {
 public:
  /// Throws FormatError if `final_path` exists and `overwrite` is false, if it is a directory,
  /// or if its directory does not exist.
  explicit AtomicOutput(std::filesystem::path final_path, bool overwrite = false);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  const std::filesystem::path& temp_path() const { return temp_path_; }
  const std::filesystem::path& final_path() const { return final_path_; }
  /// Opens `out` on temp_path() (binary, truncated), writing through `buffer`. Throws FormatError
  /// ("<who>: cannot create ...") on failure.
  void open(std::ofstream& out, std::vector<char>& buffer, const std::string& who) const;
  /// Renames the temporary file to the final name. Throws FormatError on failure.
  void commit();
  /// Flushes and closes `out` (the stream writing temp_path()), then commits. Throws
  /// FormatError ("<who>: flush failed for ..." or "close failed") on failure.
  void commit(std::ofstream& out, const std::string& who);
  bool committed() const { return committed_; }

 private:
  std::filesystem::path final_path_;
  std::filesystem::path temp_path_;
  bool committed_ = false;
};

/// What the sonar file writers (XTF, JSF, ROS 1 bag, MCAP) share: the file, written under a
/// temporary name and appearing under `path()` only when the writer's close() succeeds (an
/// AtomicOutput), and the counts of what was written.
class SonarFileWriter {
 public:
  SonarFileWriter(const SonarFileWriter&) = delete;
  SonarFileWriter& operator=(const SonarFileWriter&) = delete;

  const std::filesystem::path& path() const { return output_.final_path(); }
  std::uint64_t pings_written() const { return pings_written_; }
  std::uint64_t bytes_written() const { return bytes_written_; }
  /// Samples the format cannot hold as given (out of its range or non-finite), stored clamped;
  /// each writer says how.
  std::uint64_t clipped_samples() const { return clipped_samples_; }

 protected:
  /// Throws FormatError as AtomicOutput does.
  SonarFileWriter(std::filesystem::path path, bool overwrite)
      : output_(std::move(path), overwrite) {}
  ~SonarFileWriter() = default;

  AtomicOutput output_;
  std::uint64_t pings_written_ = 0;
  std::uint64_t bytes_written_ = 0;
  std::uint64_t clipped_samples_ = 0;
};

/// Temporary outputs (files or directories) of this process that are not committed yet.
/// AtomicOutput and OutputDirectory register theirs; a signal handler calls
/// remove_pending_temporaries() so that an interrupted run leaves nothing behind.
void register_temporary(const std::filesystem::path& path);
void unregister_temporary(const std::filesystem::path& path);
/// Removes every registered temporary (recursively) and clears the list; never throws. Holds the
/// lock that commits hold (lock_temporaries()), so it never runs in the middle of a commit.
void remove_pending_temporaries() noexcept;

/// The lock shared by commits and remove_pending_temporaries(): a commit that swaps directories
/// holds it so that an interrupt sees either the state before or the state after the swap.
class TemporariesLock {
 public:
  TemporariesLock();
  ~TemporariesLock();
  TemporariesLock(const TemporariesLock&) = delete;
  TemporariesLock& operator=(const TemporariesLock&) = delete;
};

/// True if process `pid` is running (on this machine).
bool process_is_running(long pid) noexcept;

/// Parses the process id out of a temporary's name: ".<stem>.<tag>-<pid>[-<n>]<extension>" with
/// the given `prefix` = ".<stem>.<tag>-"; returns -1 if `name` does not have that form.
long temporary_owner_pid(const std::string& name, const std::string& prefix,
                         const std::string& extension);

}  // namespace sonarsynth
