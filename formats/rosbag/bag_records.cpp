// SPDX-License-Identifier: MIT
// ROS 1 bag records and message fields, bounds-checked (docs/rosbag.md, "Reading bags with
// sonarsynth").
#include "sonarsynth/formats/rosbag/bag_records.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "sonarsynth/error.hpp"

namespace sonarsynth::rosbag::records {

void fail(const std::string& file, std::uint64_t pos, const std::string& what) {
  throw FormatError("rosbag reader: " + file + ": byte " + std::to_string(pos) + ": " + what);
}

/// Parses a header of `name=value` fields, each with a uint32 length (the record header, and a
/// connection record's data); `pos` is the file offset of `h`.
void parse_fields(std::span<const std::uint8_t> h, std::uint64_t pos, const std::string& file,
                  Fields& fields) {
  fields.clear();
  for (std::size_t k = 0; k < h.size();) {
    if (h.size() - k < 4) fail(file, pos + k, "header field length: truncated header");
    const std::uint64_t flen = le(h.data() + k, 4);
    if (flen > h.size() - k - 4) {
      fail(file, pos + k,
           "header field length = " + std::to_string(flen) + ": past the end of the header (" +
               std::to_string(h.size() - k - 4) + " bytes left)");
    }
    const std::string_view f(reinterpret_cast<const char*>(h.data() + k + 4), flen);
    const std::size_t eq = f.find('=');
    if (eq == std::string_view::npos) {
      fail(file, pos + k, "header field without '=' (" + std::to_string(flen) + " bytes)");
    }
    fields.emplace_back(f.substr(0, eq), h.subspan(k + 4 + eq + 1, flen - eq - 1));
    k += 4 + flen;
  }
}

/// Parses the record at buf[at] (file offset base + at). `with_data` = false: the buffer may end
/// after the data length (the data is not looked at).
void parse_record(std::span<const std::uint8_t> buf, std::size_t at, std::uint64_t base,
                  const std::string& file, Record& r, bool with_data) {
  r.pos = base + at;
  const std::size_t left = buf.size() - at;
  if (left < 4) {
    fail(file, r.pos,
         "record header_len: truncated record (" + std::to_string(left) + " bytes left)");
  }
  const std::uint64_t hlen = le(buf.data() + at, 4);
  if (hlen > left - 4 || left - 4 - hlen < 4) {
    fail(file, r.pos,
         "record header_len = " + std::to_string(hlen) + ": past the end (" + std::to_string(left) +
             " bytes left)");
  }
  parse_fields(buf.subspan(at + 4, hlen), r.pos + 4, file, r.fields);
  bool have_op = false;
  for (const auto& [n, v] : r.fields) {
    if (n != "op") continue;
    if (v.size() != 1) {
      fail(file, r.pos, "header field 'op' has " + std::to_string(v.size()) + " bytes, not 1");
    }
    r.op = v[0];
    have_op = true;
  }
  if (!have_op) fail(file, r.pos, "header field 'op' missing");
  const std::uint64_t dlen = le(buf.data() + at + 4 + hlen, 4);
  if (with_data && dlen > left - 8 - hlen) {
    fail(file, r.pos + 4 + hlen,
         "record data_len = " + std::to_string(dlen) + ": past the end (" +
             std::to_string(left - 8 - hlen) + " bytes left)");
  }
  r.data = with_data ? buf.subspan(at + 8 + hlen, dlen) : std::span<const std::uint8_t>{};
  r.size = static_cast<std::size_t>(8 + hlen + dlen);
}

std::span<const std::uint8_t> field(const Record& r, std::string_view name, const std::string& file,
                                    std::size_t bytes) {
  for (const auto& [n, v] : r.fields) {
    if (n != name) continue;
    if (bytes != 0 && v.size() != bytes) {
      fail(file, r.pos,
           "op " + std::to_string(r.op) + " header field '" + std::string(name) + "' has " +
               std::to_string(v.size()) + " bytes, not " + std::to_string(bytes));
    }
    return v;
  }
  fail(file, r.pos,
       "op " + std::to_string(r.op) + " header field '" + std::string(name) + "' missing");
}

std::uint64_t field_uint(const Record& r, std::string_view name, const std::string& file,
                         std::size_t bytes) {
  return le(field(r, name, file, bytes).data(), bytes);
}

std::string field_str(const Record& r, std::string_view name, const std::string& file) {
  const auto v = field(r, name, file);
  return std::string(reinterpret_cast<const char*>(v.data()), v.size());
}

void decode_samples(std::span<const std::uint8_t> bytes, std::uint32_t dtype, bool big_endian,
                    std::vector<float>& out) {
  const std::size_t bps = kDtypeBytes[dtype];
  const std::size_t n = bytes.size() / bps;
  out.resize(n);
  const std::uint8_t* p = bytes.data();
  if (dtype == 2 && !big_endian) {  // the common case: little-endian uint16
    for (std::size_t i = 0; i < n; ++i) {
      out[i] = static_cast<float>(static_cast<std::uint16_t>(p[2 * i] | (p[2 * i + 1] << 8)));
    }
    return;
  }
  for (std::size_t i = 0; i < n; ++i) {
    std::array<std::uint8_t, 8> b{};
    std::memcpy(b.data(), p + i * bps, bps);
    if (big_endian) std::reverse(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(bps));
    const std::uint64_t u = le(b.data(), bps);
    const std::int64_t sign_bit = std::int64_t{1} << (8 * bps - 1);
    const auto s = [&] {
      return bps == 8 ? static_cast<std::int64_t>(u)
                      : static_cast<std::int64_t>(u) -
                            ((static_cast<std::int64_t>(u) & sign_bit) ? 2 * sign_bit : 0);
    };
    double v = 0.0;
    switch (dtype) {
      case 1:
      case 3:
      case 5:
      case 7:
        v = static_cast<double>(s());
        break;
      case 8:
        v = static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(u)));
        break;
      case 9:
        v = std::bit_cast<double>(u);
        break;
      default:
        v = static_cast<double>(u);
        break;
    }
    out[i] = static_cast<float>(v);
  }
}

/// The heading (clockwise from north), pitch (+ nose up) and roll (+ starboard down) of an ENU
/// orientation of base_link: the writer's yaw = pi/2 - heading, pitch = -pitch, roll = roll
/// reversed (docs/rosbag.md, "sensor_msgs/Imu").
bool attitude_from_quaternion(double x, double y, double z, double w, AttitudeSample& a) {
  const double norm = std::sqrt(x * x + y * y + z * z + w * w);
  if (!std::isfinite(norm) || std::abs(norm - 1.0) > 1e-3) return false;
  x /= norm, y /= norm, z /= norm, w /= norm;
  const double roll = std::atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y));
  const double pitch = std::asin(std::clamp(2 * (w * y - z * x), -1.0, 1.0));
  const double yaw = std::atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
  double heading = std::fmod(std::numbers::pi / 2 - yaw, 2 * std::numbers::pi);
  if (heading < 0) heading += 2 * std::numbers::pi;
  a.heading_true_rad = heading;
  a.pitch_rad = -pitch;
  a.roll_rad = roll;
  return true;
}

}  // namespace sonarsynth::rosbag::records
