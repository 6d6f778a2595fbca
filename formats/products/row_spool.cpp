// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/products/row_spool.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/products/waterfall.hpp"

namespace sonarsynth::detail {
namespace {

constexpr std::size_t kHeaderBytes = 2 * sizeof(std::uint64_t);

}  // namespace

SideSpool::SideSpool(const std::filesystem::path& dir, std::size_t bands, std::string who)
    : who_(std::move(who)), dir_(dir), bands_(bands) {
  std::error_code ec;
  if (dir_.empty()) dir_ = std::filesystem::temp_directory_path(ec);
  if (ec) throw FormatError(who_ + ": no temporary directory for the spool file: " + ec.message());
  std::string name = (dir_ / ".sonarsynth-spool-XXXXXX").string();
  fd_ = ::mkstemp(name.data());
  if (fd_ < 0) {
    throw FormatError(who_ + ": cannot create a spool file in " + dir_.string() + ": " +
                      std::strerror(errno));
  }
  // Nameless from now on: the space is freed when the descriptor is closed, even by a crash.
  ::unlink(name.c_str());
  ::fcntl(fd_, F_SETFD, FD_CLOEXEC);
}

SideSpool::~SideSpool() {
  if (fd_ >= 0) ::close(fd_);
}

void SideSpool::append(std::span<const std::span<const float>> port,
                       std::span<const std::span<const float>> starboard) {
  if (port.size() != bands_ || starboard.size() != bands_) {
    throw std::logic_error(who_ + ": spool row with the wrong number of bands");
  }
  const std::size_t np = port[0].size();
  const std::size_t ns = starboard[0].size();
  for (std::size_t b = 0; b < bands_; ++b) {
    if (port[b].size() != np || starboard[b].size() != ns) {
      throw std::logic_error(who_ + ": spool row with bands of different sizes");
    }
  }
  buffer_.resize(kHeaderBytes + sizeof(float) * bands_ * (np + ns));
  unsigned char* p = buffer_.data();
  const std::uint64_t header[2] = {np, ns};
  std::memcpy(p, header, kHeaderBytes);
  p += kHeaderBytes;
  for (const auto* side : {&port, &starboard}) {
    for (const std::span<const float> band : *side) {
      if (!band.empty()) std::memcpy(p, band.data(), band.size_bytes());
      p += band.size_bytes();
    }
  }
  // pwrite at the end of the last complete row: a row that fails half-way is overwritten by
  // the next one.
  std::size_t done = 0;
  while (done < buffer_.size()) {
    const ssize_t n = ::pwrite(fd_, buffer_.data() + done, buffer_.size() - done,
                               static_cast<off_t>(size_ + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      throw FormatError(who_ + ": cannot write the spool file in " + dir_.string() + ": " +
                        (n < 0 ? std::strerror(errno) : "nothing written"));
    }
    done += static_cast<std::size_t>(n);
  }
  size_ += buffer_.size();
  ++rows_;
  side_ = std::max({side_, np, ns});
}

void SideSpool::read_at(std::uint64_t offset, void* data, std::size_t bytes) const {
  auto* p = static_cast<unsigned char*>(data);
  std::size_t done = 0;
  while (done < bytes) {
    const ssize_t n = ::pread(fd_, p + done, bytes - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      throw FormatError(who_ + ": cannot read the spool file in " + dir_.string() + ": " +
                        (n < 0 ? std::strerror(errno) : "unexpected end of file"));
    }
    done += static_cast<std::size_t>(n);
  }
}

SideSpool::Reader::Reader(const SideSpool& spool, std::span<const float> pads)
    : spool_(spool), pads_(pads.begin(), pads.end()) {
  if (pads_.size() != spool_.bands_) {
    throw std::logic_error(spool_.who_ + ": spool reader with the wrong number of pads");
  }
}

bool SideSpool::Reader::next(std::span<float> out) {
  const std::size_t side = spool_.side_;
  const std::size_t cols = 2 * side;
  if (out.size() != spool_.bands_ * cols) {
    throw std::logic_error(spool_.who_ + ": spool reader given a row of the wrong size");
  }
  if (offset_ >= spool_.size_) return false;
  std::uint64_t header[2];
  spool_.read_at(offset_, header, kHeaderBytes);
  if (header[0] > side || header[1] > side) {
    throw FormatError(spool_.who_ + ": spool file in " + spool_.dir_.string() + " is corrupt");
  }
  const auto np = static_cast<std::size_t>(header[0]);
  const auto ns = static_cast<std::size_t>(header[1]);
  buffer_.resize(spool_.bands_ * (np + ns));
  spool_.read_at(offset_ + kHeaderBytes, buffer_.data(), sizeof(float) * buffer_.size());
  offset_ += kHeaderBytes + sizeof(float) * buffer_.size();
  const float* port = buffer_.data();
  const float* stbd = port + spool_.bands_ * np;
  for (std::size_t b = 0; b < spool_.bands_; ++b) {
    float* row = out.data() + b * cols;
    std::fill(row, row + cols, pads_[b]);
    const float* p = port + b * np;
    for (std::size_t i = 0; i < np; ++i) row[side - 1 - i] = p[i];  // far -> near
    std::copy(stbd + b * ns, stbd + (b + 1) * ns, row + side);
  }
  return true;
}

void SideSpool::Reader::rewind() {
  offset_ = 0;
}

SpooledRows::SpooledRows() = default;
SpooledRows::SpooledRows(std::unique_ptr<SideSpool> spool) : spool_(std::move(spool)) {}
SpooledRows::~SpooledRows() = default;
SpooledRows::SpooledRows(SpooledRows&&) noexcept = default;
SpooledRows& SpooledRows::operator=(SpooledRows&&) noexcept = default;

std::size_t SpooledRows::rows() const {
  return spool_ ? spool_->rows() : 0;
}

std::size_t SpooledRows::cols() const {
  return spool_ ? spool_->cols() : 0;
}

}  // namespace sonarsynth::detail
