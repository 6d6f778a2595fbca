// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

namespace sonarsynth::detail {

/// A temporary file of fixed-place records (positional reads and writes; places never written
/// take no space in a sparse file), created under a unique name in a directory and removed by
/// the destructor, whatever happened.
class SpillFile {
 public:
  /// Creates ".sonarsynth_<who>_spill_XXXXXX" in `dir`; throws FormatError("<who>: ...") naming
  /// the directory if it cannot.
  SpillFile(const std::filesystem::path& dir, std::string who);
  ~SpillFile();
  SpillFile(const SpillFile&) = delete;
  SpillFile& operator=(const SpillFile&) = delete;

  const std::filesystem::path& path() const { return path_; }
  /// Throw FormatError naming the file on failure.
  void write(std::uint64_t offset, const void* data, std::size_t bytes);
  void read(std::uint64_t offset, void* data, std::size_t bytes) const;

 private:
  [[noreturn]] void fail(const char* what) const;
  int fd_ = -1;
  std::filesystem::path path_;
  std::string who_;
};

}  // namespace sonarsynth::detail
