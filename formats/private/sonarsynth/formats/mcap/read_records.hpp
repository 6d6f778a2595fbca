// SPDX-License-Identifier: MIT
// Bounds-checked reading of MCAP record fields and of ROS 2 CDR messages (docs/robotics.md,
// "Reading bags"): every error is a FormatError naming the file, the byte offset and the field.
// Used by formats/mcap/reader.cpp and formats/mcap/read_messages.cpp.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>

namespace sonarsynth::mcap::read {

/// Where a byte is: a file offset, or an offset in the decompressed records of the chunk at
/// file offset `chunk` (when not 0).
struct Where {
  const std::string& file;
  std::uint64_t chunk = 0;
};

/// "byte 123" or "chunk at byte 123, uncompressed byte 45".
std::string position(const Where& w, std::uint64_t at);

/// Throws FormatError "mcap reader: <file>: <position>: <what>".
[[noreturn]] void fail(const Where& w, std::uint64_t at, const std::string& what);

/// The little-endian unsigned integer of the `n` (<= 8) bytes at `p`.
inline std::uint64_t le(const std::uint8_t* p, std::size_t n) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < n; ++i) v |= static_cast<std::uint64_t>(p[i]) << (8 * i);
  return v;
}

/// The fields of one record's content (or of a CDR message after its encapsulation header:
/// `align` true aligns each primitive to its size, at most 8, from the first byte of `d`).
class Fields {
 public:
  Fields(std::span<const std::uint8_t> d, std::uint64_t base, const Where& where,
         std::string_view record, bool align = false)
      : d_(d), base_(base), where_(where), record_(record), align_(align) {}

  std::span<const std::uint8_t> take(std::size_t n, const char* f) {
    if (n > d_.size() - pos_) {
      fail(where_, base_ + pos_,
           std::string(record_) + "." + f + ": needs " + std::to_string(n) + " bytes, " +
               std::to_string(d_.size() - pos_) + " left in the " +
               (align_ ? "message" : "record"));
    }
    pos_ += n;
    return d_.subspan(pos_ - n, n);
  }
  std::uint64_t uint(std::size_t n, const char* f) {
    if (align_) pos_ = std::min(d_.size(), (pos_ + n - 1) / n * n);
    return le(take(n, f).data(), n);
  }
  std::uint8_t u8(const char* f) { return static_cast<std::uint8_t>(uint(1, f)); }
  std::uint16_t u16(const char* f) { return static_cast<std::uint16_t>(uint(2, f)); }
  std::uint32_t u32(const char* f) { return static_cast<std::uint32_t>(uint(4, f)); }
  std::uint64_t u64(const char* f) { return uint(8, f); }
  float f32(const char* f) { return std::bit_cast<float>(u32(f)); }
  double f64(const char* f) { return std::bit_cast<double>(u64(f)); }
  /// u32 length then the bytes (an MCAP string or byte array).
  std::span<const std::uint8_t> bytes(const char* f) {
    const std::uint32_t n = u32(f);
    return take(n, f);
  }
  std::string_view str(const char* f) {
    const auto s = bytes(f);
    return {reinterpret_cast<const char*>(s.data()), s.size()};
  }
  std::size_t left() const { return d_.size() - pos_; }
  std::uint64_t offset() const { return base_ + pos_; }
  [[noreturn]] void fail_at(const std::string& what) const { fail(where_, base_ + pos_, what); }

 private:
  std::span<const std::uint8_t> d_;
  std::size_t pos_ = 0;
  std::uint64_t base_;
  const Where& where_;
  std::string_view record_;
  bool align_;
};

/// A ROS 2 CDR message: checks the encapsulation header (plain CDR, little endian: 00 01) and
/// reads the fields after it, aligned as XCDR1 aligns them.
class Cdr : public Fields {
 public:
  Cdr(std::span<const std::uint8_t> m, std::uint64_t base, const Where& where,
      std::string_view type)
      : Fields(m.size() >= 4 ? m.subspan(4) : m.subspan(m.size()), base + 4, where, type, true),
        type_(type) {
    if (m.size() < 4) {
      fail(where, base,
           std::string(type) + ": " + std::to_string(m.size()) +
               " bytes, shorter than the 4-byte CDR encapsulation header");
    }
    if (m[0] != 0x00 || m[1] != 0x01) {
      const bool big = m[0] == 0x00 && m[1] == 0x00;
      fail(where, base,
           std::string(type) + ": CDR encapsulation " + std::to_string(m[0]) + " " +
               std::to_string(m[1]) +
               (big ? ": big-endian CDR is not read" : ": not plain little-endian CDR (00 01)"));
    }
  }
  /// std_msgs/Header: returns the stamp in ns, the frame id through `frame`.
  std::uint64_t header(std::string_view& frame) {
    const auto sec = static_cast<std::int32_t>(u32("header.stamp.sec"));
    const std::uint32_t nsec = u32("header.stamp.nanosec");
    if (sec < 0 || nsec >= 1000000000u) {
      fail_at(std::string(type_) + ".header.stamp = " + std::to_string(sec) + " s " +
              std::to_string(nsec) + " ns. Violated constraint: sec >= 0, nanosec < 1000000000");
    }
    frame = str("header.frame_id");
    if (!frame.empty() && frame.back() == '\0') frame.remove_suffix(1);
    return static_cast<std::uint64_t>(sec) * 1000000000u + nsec;
  }
  /// A float32[]: its first element, 0 when empty.
  double first_f32(const char* f) {
    const std::uint32_t n = u32(f);
    if (n > left() / 4) take(std::size_t{n} * 4, f);  // reports the overrun
    const auto s = take(std::size_t{n} * 4, f);
    return n == 0 ? 0.0
                  : static_cast<double>(
                        std::bit_cast<float>(static_cast<std::uint32_t>(le(s.data(), 4))));
  }

 private:
  std::string_view type_;
};

}  // namespace sonarsynth::mcap::read
