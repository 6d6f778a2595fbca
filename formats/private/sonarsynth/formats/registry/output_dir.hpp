// SPDX-License-Identifier: MIT
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace sonarsynth {

/// An output directory that appears under its final name only when everything in it is
/// complete: files are written into a hidden sibling directory, which commit() moves into place.
///
/// Safety rules (each violation throws FormatError naming the directory and the reason, before
/// anything is created or removed):
/// - `final_dir` may not be "/", the working directory or any of its ancestors, nor contain any
///   of `inputs` (the scene file, say): replacing it would delete them.
/// - An existing `final_dir` is replaced only with `overwrite`, and only if it is empty or is a
///   sonarsynth output: it holds the marker file kMarkerName (or, from versions before the marker,
///   effective.yaml) and nothing but files with the extensions sonarsynth writes.
/// - Replacing is an atomic exchange (renameat2 RENAME_EXCHANGE; where the file system lacks it,
///   two renames with the old directory set aside first), then the old directory is deleted: a
///   kill at any moment leaves the old or the new results complete under the final name (or, in
///   the two-rename fallback, the old ones set aside, which the next run puts back).
/// - While not committed the temporary directory is registered for remove_pending_temporaries()
///   (the CLI's SIGINT/SIGTERM handler); temporaries of processes that no longer run are removed
///   when the next OutputDirectory for the same name is created.
/// Destroyed without commit(), it removes the temporary directory: no partial output is left.
class OutputDirectory {
 public:
  /// Name of the marker file written into every output directory.
  static constexpr const char* kMarkerName = ".sonarsynth-output";

  OutputDirectory(std::filesystem::path final_dir, bool overwrite,
                  const std::vector<std::filesystem::path>& inputs = {});
  ~OutputDirectory();
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;

  /// Where to write (inside the temporary directory).
  std::filesystem::path file(const std::string& name) const { return temp_ / name; }
  const std::filesystem::path& final_dir() const { return final_; }
  const std::filesystem::path& temp_dir() const { return temp_; }
  void commit();

 private:
  std::filesystem::path final_;
  std::filesystem::path temp_;
  bool overwrite_;
  bool committed_ = false;
};

/// Why `dir` (an existing directory) is not one that OutputDirectory may replace: the empty
/// string if it may, else a reason naming the offending entry.
std::string why_not_replaceable_output(const std::filesystem::path& dir);

}  // namespace sonarsynth
