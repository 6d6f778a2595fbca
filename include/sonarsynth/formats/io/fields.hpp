// SPDX-License-Identifier: MIT
#pragma once

// Field tables: each binary record lists its fields once, in file order and with their
// little-endian widths, in a static member template
//
//   template <class IO, class Self> static constexpr void fields(IO& io, Self& s) {
//     io.u16(s.MagicNumber);
//     io.u8(s.HeaderType);
//     ...
//   }
//
// and three IOs walk that one list: FieldReader decodes (through ByteReader), FieldWriter
// encodes (through ByteWriter) and FieldCounter adds up the widths, at compile time, so that a
// static_assert ties the table to the record's kSize. `Self` is the record for reading and the
// const record for writing. FieldReader takes each field by non-const reference to exactly the
// named type, so a table that names the wrong width for a field does not compile. The fields
// are still read and written one by one in explicit little-endian; no struct is ever copied
// from or to raw bytes.

#include <array>
#include <cstddef>
#include <cstdint>

#include "sonarsynth/formats/io/byte_io.hpp"

namespace sonarsynth {

/// Decodes a field table from a ByteReader.
class FieldReader {
 public:
  explicit FieldReader(ByteReader& r) : r_(r) {}
  void u8(std::uint8_t& v) { v = r_.u8(); }
  void u16(std::uint16_t& v) { v = r_.u16(); }
  void u32(std::uint32_t& v) { v = r_.u32(); }
  void i16(std::int16_t& v) { v = r_.i16(); }
  void i32(std::int32_t& v) { v = r_.i32(); }
  void f32(float& v) { v = r_.f32(); }
  void f64(double& v) { v = r_.f64(); }
  template <std::size_t N>
  void bytes(std::array<std::uint8_t, N>& a) {
    r_.bytes(a);
  }
  template <std::size_t N>
  void chars(std::array<char, N>& a) {
    r_.chars(a);
  }
  /// `n` bytes the record does not keep: skipped.
  void reserved(std::size_t n) { r_.skip(n); }

 private:
  ByteReader& r_;
};

/// Encodes a field table into a ByteWriter.
class FieldWriter {
 public:
  explicit FieldWriter(ByteWriter& w) : w_(w) {}
  void u8(std::uint8_t v) { w_.u8(v); }
  void u16(std::uint16_t v) { w_.u16(v); }
  void u32(std::uint32_t v) { w_.u32(v); }
  void i16(std::int16_t v) { w_.i16(v); }
  void i32(std::int32_t v) { w_.i32(v); }
  void f32(float v) { w_.f32(v); }
  void f64(double v) { w_.f64(v); }
  template <std::size_t N>
  void bytes(const std::array<std::uint8_t, N>& a) {
    w_.bytes(a);
  }
  template <std::size_t N>
  void chars(const std::array<char, N>& a) {
    w_.chars(a);
  }
  /// `n` bytes the record does not keep: written as zeros.
  void reserved(std::size_t n) { w_.zeros(n); }

 private:
  ByteWriter& w_;
};

/// Adds up the byte widths of a field table (usable in constant expressions).
class FieldCounter {
 public:
  constexpr std::size_t size() const { return size_; }
  constexpr void u8(std::uint8_t) { size_ += 1; }
  constexpr void u16(std::uint16_t) { size_ += 2; }
  constexpr void u32(std::uint32_t) { size_ += 4; }
  constexpr void i16(std::int16_t) { size_ += 2; }
  constexpr void i32(std::int32_t) { size_ += 4; }
  constexpr void f32(float) { size_ += 4; }
  constexpr void f64(double) { size_ += 8; }
  template <std::size_t N>
  constexpr void bytes(const std::array<std::uint8_t, N>&) {
    size_ += N;
  }
  template <std::size_t N>
  constexpr void chars(const std::array<char, N>&) {
    size_ += N;
  }
  constexpr void reserved(std::size_t n) { size_ += n; }

 private:
  std::size_t size_ = 0;
};

/// The number of bytes `Record::fields` reads and writes: compare with Record::kSize.
template <class Record>
constexpr std::size_t field_table_size() {
  FieldCounter c;
  const Record r{};
  Record::fields(c, r);
  return c.size();
}

/// Writes `r` field by field, as its table lists them.
template <class Record>
void write_fields(ByteWriter& w, const Record& r) {
  FieldWriter io(w);
  Record::fields(io, r);
}

/// Reads a `Record` field by field, as its table lists them.
template <class Record>
Record read_fields(ByteReader& r) {
  Record rec;
  FieldReader io(r);
  Record::fields(io, rec);
  return rec;
}

}  // namespace sonarsynth
