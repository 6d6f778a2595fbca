// SPDX-License-Identifier: MIT
#pragma once

#include <filesystem>

namespace sonarsynth {

/// A file that appears under its final name only when complete.
///
/// Write to temp_path() (a hidden name in the same directory, so the rename is atomic), then call
/// commit(). If the object is destroyed without commit() — an exception, a crash of the writer —
/// the temporary file is removed and nothing is left that looks like a complete output.
class AtomicOutput {
 public:
  /// Throws FormatError if `final_path` exists and `overwrite` is false, or if its directory
  /// does not exist.
  explicit AtomicOutput(std::filesystem::path final_path, bool overwrite = false);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  const std::filesystem::path& temp_path() const { return temp_path_; }
  const std::filesystem::path& final_path() const { return final_path_; }
  /// Renames the temporary file to the final name. Throws FormatError on failure.
  void commit();
  bool committed() const { return committed_; }

 private:
  std::filesystem::path final_path_;
  std::filesystem::path temp_path_;
  bool committed_ = false;
};

}  // namespace sonarsynth
