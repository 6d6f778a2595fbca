// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>

#include "sonarsynth/error.hpp"

namespace sonarsynth {

/// Bounds-checked little-endian writer over a caller-owned byte span, for every binary codec.
/// Multi-byte values are assembled byte by byte (independent of the host byte order); floats go
/// through std::bit_cast to their integer bit pattern. Writing past the end throws FormatError.
class ByteWriter {
 public:
  /// `who` starts error messages ("xtf", "jsf").
  explicit ByteWriter(std::span<std::uint8_t> bytes, const char* who = "xtf")
      : bytes_(bytes), who_(who) {}

  std::size_t position() const { return pos_; }
  std::size_t size() const { return bytes_.size(); }

  void u8(std::uint8_t v) { put(v, 1); }
  void u16(std::uint16_t v) { put(v, 2); }
  void u32(std::uint32_t v) { put(v, 4); }
  void u64(std::uint64_t v) { put(v, 8); }
  void i8(std::int8_t v) { put(static_cast<std::uint8_t>(v), 1); }
  void i16(std::int16_t v) { put(static_cast<std::uint16_t>(v), 2); }
  void i32(std::int32_t v) { put(static_cast<std::uint32_t>(v), 4); }
  void f32(float v) { put(std::bit_cast<std::uint32_t>(v), 4); }
  void f64(double v) { put(std::bit_cast<std::uint64_t>(v), 8); }
  /// Reserves the next `n` bytes (bounds-checked once) for the caller to fill, e.g. a block of
  /// samples; returns them as a span.
  std::span<std::uint8_t> take(std::size_t n) {
    check(n);
    const std::span<std::uint8_t> out = bytes_.subspan(pos_, n);
    pos_ += n;
    return out;
  }
  /// Writes `n` zero bytes.
  void zeros(std::size_t n) {
    check(n);
    std::memset(bytes_.data() + pos_, 0, n);
    pos_ += n;
  }
  template <std::size_t N>
  void bytes(const std::array<std::uint8_t, N>& a) {
    check(N);
    std::memcpy(bytes_.data() + pos_, a.data(), N);
    pos_ += N;
  }
  template <std::size_t N>
  void chars(const std::array<char, N>& a) {
    check(N);
    std::memcpy(bytes_.data() + pos_, a.data(), N);
    pos_ += N;
  }

 private:
  void check(std::size_t n) const {
    if (n > bytes_.size() - pos_) {
      throw FormatError(std::string(who_) + ": write of " + std::to_string(n) +
                        " bytes at offset " + std::to_string(pos_) + " overruns a " +
                        std::to_string(bytes_.size()) + "-byte record buffer");
    }
  }
  void put(std::uint64_t v, std::size_t n) {
    check(n);
    for (std::size_t i = 0; i < n; ++i) {
      bytes_[pos_ + i] = static_cast<std::uint8_t>((v >> (8 * i)) & 0xFFu);
    }
    pos_ += n;
  }

  std::span<std::uint8_t> bytes_;
  const char* who_;
  std::size_t pos_ = 0;
};

/// Bounds-checked little-endian reader over a byte span (the counterpart of ByteWriter).
/// Reading past the end throws FormatError.
class ByteReader {
 public:
  /// `who` starts error messages ("xtf", "jsf").
  explicit ByteReader(std::span<const std::uint8_t> bytes, const char* who = "xtf")
      : bytes_(bytes), who_(who) {}

  std::size_t position() const { return pos_; }
  std::size_t size() const { return bytes_.size(); }
  std::size_t remaining() const { return bytes_.size() - pos_; }
  void skip(std::size_t n) {
    check(n);
    pos_ += n;
  }

  std::uint8_t u8() { return static_cast<std::uint8_t>(get(1)); }
  std::uint16_t u16() { return static_cast<std::uint16_t>(get(2)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(get(4)); }
  std::uint64_t u64() { return get(8); }
  std::int8_t i8() { return static_cast<std::int8_t>(u8()); }
  std::int16_t i16() { return static_cast<std::int16_t>(u16()); }
  std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
  float f32() { return std::bit_cast<float>(u32()); }
  double f64() { return std::bit_cast<double>(u64()); }
  template <std::size_t N>
  void bytes(std::array<std::uint8_t, N>& a) {
    check(N);
    std::memcpy(a.data(), bytes_.data() + pos_, N);
    pos_ += N;
  }
  template <std::size_t N>
  void chars(std::array<char, N>& a) {
    check(N);
    std::memcpy(a.data(), bytes_.data() + pos_, N);
    pos_ += N;
  }

 private:
  void check(std::size_t n) const {
    if (n > bytes_.size() - pos_) {
      throw FormatError(std::string(who_) + ": read of " + std::to_string(n) + " bytes at offset " +
                        std::to_string(pos_) + " overruns a " + std::to_string(bytes_.size()) +
                        "-byte record");
    }
  }
  std::uint64_t get(std::size_t n) {
    check(n);
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < n; ++i) {
      v |= static_cast<std::uint64_t>(bytes_[pos_ + i]) << (8 * i);
    }
    pos_ += n;
    return v;
  }

  std::span<const std::uint8_t> bytes_;
  const char* who_;
  std::size_t pos_ = 0;
};

/// Copies `s` into a fixed-size, NUL-padded character field (truncated if longer; a full field
/// has no terminating NUL, as the spec allows).
template <std::size_t N>
std::array<char, N> fixed_string(std::string_view s) {
  std::array<char, N> a{};
  std::memcpy(a.data(), s.data(), s.size() < N ? s.size() : N);
  return a;
}

/// The text of a NUL-padded character field (stops at the first NUL or at the end).
template <std::size_t N>
std::string to_string(const std::array<char, N>& a) {
  std::size_t n = 0;
  while (n < N && a[n] != '\0') ++n;
  return std::string(a.data(), n);
}

}  // namespace sonarsynth
