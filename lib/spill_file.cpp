// SPDX-License-Identifier: MIT
#include "sonarsynth/spill_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>
#include <utility>

#include "sonarsynth/error.hpp"

namespace sonarsynth::detail {

SpillFile::SpillFile(const std::filesystem::path& dir, std::string who) : who_(std::move(who)) {
  std::string name = (dir / (".sonarsynth_" + who_ + "_spill_XXXXXX")).string();
  fd_ = ::mkstemp(name.data());
  if (fd_ < 0) {
    throw FormatError(who_ + ": cannot create a spill file in " + dir.string() + ": " +
                      std::strerror(errno));
  }
  path_ = name;
}

SpillFile::~SpillFile() {
  ::close(fd_);
  std::error_code ignored;
  std::filesystem::remove(path_, ignored);
}

namespace {

/// Calls `io` (::pwrite or ::pread) until all `bytes` are done, again after EINTR; false if it
/// fails (errno says why) or reaches the end of the file.
template <class Byte, class Io>
bool transfer_all(Io io, int fd, Byte* p, std::size_t bytes, std::uint64_t offset) {
  while (bytes > 0) {
    const ssize_t n = io(fd, p, bytes, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    bytes -= static_cast<std::size_t>(n);
    offset += static_cast<std::uint64_t>(n);
  }
  return true;
}

}  // namespace

void SpillFile::write(std::uint64_t offset, const void* data, std::size_t bytes) {
  if (!transfer_all(::pwrite, fd_, static_cast<const char*>(data), bytes, offset)) fail("write");
}

void SpillFile::read(std::uint64_t offset, void* data, std::size_t bytes) const {
  if (!transfer_all(::pread, fd_, static_cast<char*>(data), bytes, offset)) fail("read");
}

void SpillFile::fail(const char* what) const {
  const int e = errno;
  throw FormatError(who_ + ": spill file " + path_.string() + ": cannot " + what + ": " +
                    (e ? std::strerror(e) : "end of file"));
}

}  // namespace sonarsynth::detail
