// SPDX-License-Identifier: MIT
#pragma once

#include <filesystem>

namespace sonarsynth {

/// An output directory that appears under its final name only when everything in it is
/// complete: files are written into a hidden sibling directory, which commit() renames into
/// place (replacing an existing directory only when `overwrite`). Destroyed without commit(),
/// it removes the temporary directory: no partial output is left.
class OutputDirectory {
 public:
  /// Throws FormatError if `final_dir` exists and `overwrite` is false, or its parent does not
  /// exist.
  OutputDirectory(std::filesystem::path final_dir, bool overwrite);
  ~OutputDirectory();
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;

  /// Where to write (inside the temporary directory).
  std::filesystem::path file(const std::string& name) const { return temp_ / name; }
  const std::filesystem::path& final_dir() const { return final_; }
  void commit();

 private:
  std::filesystem::path final_;
  std::filesystem::path temp_;
  bool overwrite_;
  bool committed_ = false;
};

}  // namespace sonarsynth
