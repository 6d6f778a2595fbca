// SPDX-License-Identifier: MIT
#pragma once
// Private helper of the waterfall writers: the rows of a port | starboard image kept in a
// temporary file instead of memory, read back in order and assembled into image rows.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace sonarsynth::detail {

/// Rows of `bands` float arrays per side (NEAR -> FAR), appended to a temporary file.
///
/// The file is created in `dir` and unlinked at once: it has no name while in use, so it never
/// shows up among the outputs and disappears when the spool is destroyed, whether by an
/// exception or the end of the process. Each row is a header (port length, starboard length;
/// uint64) followed by the port arrays then the starboard arrays (float32, band by band), in the
/// byte order of the machine (the file never leaves the process).
class SideSpool {
 public:
  /// Throws FormatError("<who>: cannot create a spool file in <dir>: ...").
  SideSpool(const std::filesystem::path& dir, std::size_t bands, std::string who);
  ~SideSpool();
  SideSpool(const SideSpool&) = delete;
  SideSpool& operator=(const SideSpool&) = delete;

  /// Appends a row: `port[b]` and `starboard[b]` for each band b (`bands` spans each; the spans
  /// of a side have one size, which may differ between sides and rows). Throws FormatError if the
  /// file cannot be written (e.g. a full disk).
  void append(std::span<const std::span<const float>> port,
              std::span<const std::span<const float>> starboard);
  std::size_t bands() const { return bands_; }
  std::size_t rows() const { return rows_; }
  /// Longest side appended so far.
  std::size_t side() const { return side_; }
  /// 2 x side(): port FAR -> NEAR, then starboard NEAR -> FAR.
  std::size_t cols() const { return 2 * side_; }

  /// Reads the rows back in order as image rows of cols() pixels per band.
  class Reader {
   public:
    /// `pads`: the value of pixels beyond a side's samples, per band.
    Reader(const SideSpool& spool, std::span<const float> pads);
    /// Fills `out` (bands x cols(), band by band) with the next row; false after the last.
    /// Throws FormatError if the file cannot be read.
    bool next(std::span<float> out);
    /// Restarts at the first row.
    void rewind();

   private:
    const SideSpool& spool_;
    std::vector<float> pads_;
    std::uint64_t offset_ = 0;
    std::vector<float> buffer_;
  };

 private:
  void read_at(std::uint64_t offset, void* data, std::size_t bytes) const;

  std::string who_;
  std::filesystem::path dir_;
  std::size_t bands_;
  int fd_ = -1;
  std::uint64_t size_ = 0;  ///< bytes written
  std::size_t rows_ = 0;
  std::size_t side_ = 0;
  std::vector<unsigned char> buffer_;  ///< one row being written
};

}  // namespace sonarsynth::detail
