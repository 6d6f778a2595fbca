// SPDX-License-Identifier: MIT
// ROS 1 bag writer, format 2.0 (docs/rosbag.md): records, chunks, index, messages.
#include "sonarsynth/formats/rosbag/writer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <string_view>
#include <utility>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/byte_io.hpp"
#include "sonarsynth/formats/rosbag/bag_records.hpp"
#include "sonarsynth/formats/rosbag/message_bytes.hpp"
#include "sonarsynth/formats/rosbag/messages.hpp"
#include "sonarsynth/formats/rosbag/quaternion.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::rosbag {
namespace {

constexpr std::size_t kBagHeaderBytes = 4096;  // the bag header record, padded with spaces

// The truth connections appear only in a bag given truth (Writer::write_truth).
enum Conn : std::uint32_t {
  kPort = 0,
  kStarboard,
  kFix,
  kImu,
  kTfStatic,
  kPortTruth,
  kStarboardTruth,
  kConnCount
};

struct Connection {
  const char* topic;
  const char* type;
  bool latching;
};
constexpr std::array<Connection, kConnCount> kConnections = {{
    {kPortTopic, "marine_acoustic_msgs/RawSonarImage", false},
    {kStarboardTopic, "marine_acoustic_msgs/RawSonarImage", false},
    {kFixTopic, "sensor_msgs/NavSatFix", false},
    {kImuTopic, "sensor_msgs/Imu", false},
    {kTfStaticTopic, "tf2_msgs/TFMessage", true},
    {kPortTruthTopic, "sonarsynth_msgs/SideScanTruth", false},
    {kStarboardTruthTopic, "sonarsynth_msgs/SideScanTruth", false},
}};

/// Appends little-endian fields to a growing byte vector (through ByteWriter).
class Out {
 public:
  explicit Out(std::vector<std::uint8_t>& b) : b_(b) {}
  std::size_t size() const { return b_.size(); }
  ByteWriter take(std::size_t n) {
    const std::size_t o = b_.size();
    b_.resize(o + n);
    return ByteWriter(std::span<std::uint8_t>(b_).subspan(o, n), "rosbag");
  }
  void u8(std::uint8_t v) { take(1).u8(v); }
  void i8(std::int8_t v) { take(1).i8(v); }
  void u16(std::uint16_t v) { take(2).u16(v); }
  void u32(std::uint32_t v) { take(4).u32(v); }
  void u64(std::uint64_t v) { take(8).u64(v); }
  void f32(float v) { take(4).f32(v); }
  void f64(double v) { take(8).f64(v); }
  void raw(std::string_view s) {
    if (!s.empty()) std::memcpy(take(s.size()).take(s.size()).data(), s.data(), s.size());
  }
  /// ROS string: uint32 length, bytes.
  void str(std::string_view s) {
    u32(static_cast<std::uint32_t>(s.size()));
    raw(s);
  }
  /// ROS time: uint32 seconds, uint32 nanoseconds.
  void time(std::uint64_t ns) {
    u32(static_cast<std::uint32_t>(ns / 1000000000u));
    u32(static_cast<std::uint32_t>(ns % 1000000000u));
  }
  /// A float32[] of at most one element (none when `v` is 0 = unknown).
  void f32_array(double v, bool keep_zero = false) {
    u32(v != 0.0 || keep_zero ? 1u : 0u);
    if (v != 0.0 || keep_zero) f32(static_cast<float>(v));
  }
  /// Reserves a uint32 length; close_length() fills it with the bytes appended since.
  std::size_t open_length() {
    u32(0);
    return b_.size();
  }
  void close_length(std::size_t start) {
    ByteWriter(std::span<std::uint8_t>(b_).subspan(start - 4, 4), "rosbag")
        .u32(static_cast<std::uint32_t>(b_.size() - start));
  }
  // Record header fields: uint32 length, "name=", value.
  template <class F>
  void field(std::string_view name, F&& value) {
    const std::size_t s = open_length();
    raw(name);
    raw("=");
    value(*this);
    close_length(s);
  }
  void field_u8(std::string_view n, std::uint8_t v) {
    field(n, [&](Out& o) { o.u8(v); });
  }
  void field_u32(std::string_view n, std::uint32_t v) {
    field(n, [&](Out& o) { o.u32(v); });
  }
  void field_u64(std::string_view n, std::uint64_t v) {
    field(n, [&](Out& o) { o.u64(v); });
  }
  void field_time(std::string_view n, std::uint64_t ns) {
    field(n, [&](Out& o) { o.time(ns); });
  }
  void field_str(std::string_view n, std::string_view v) {
    field(n, [&](Out& o) { o.raw(v); });
  }

 private:
  std::vector<std::uint8_t>& b_;
};

void put_header(Out& o, std::uint32_t seq, std::uint64_t ns, std::string_view frame) {
  o.u32(seq);
  o.time(ns);
  o.str(frame);
}

struct ConnectionTexts {
  std::string md5sum;
  std::string definition;
};

/// Each connection's md5sum and message definition, computed once.
const std::array<ConnectionTexts, kConnCount>& connection_texts() {
  static const std::array<ConnectionTexts, kConnCount> v = [] {
    std::array<ConnectionTexts, kConnCount> a;
    for (std::size_t i = 0; i < kConnCount; ++i) {
      a[i] = {message_md5(kConnections[i].type), message_definition(kConnections[i].type)};
    }
    return a;
  }();
  return v;
}

void put_connection(Out& o, std::uint32_t conn) {
  const Connection& c = kConnections[conn];
  const std::size_t h = o.open_length();
  o.field_u8("op", kOpConnection);
  o.field_u32("conn", conn);
  o.field_str("topic", c.topic);
  o.close_length(h);
  const std::size_t d = o.open_length();
  o.field_str("topic", c.topic);
  o.field_str("type", c.type);
  o.field_str("md5sum", connection_texts()[conn].md5sum);
  o.field_str("message_definition", connection_texts()[conn].definition);
  if (c.latching) o.field_str("latching", "1");
  o.close_length(d);
}

void put_bag_header(Out& o, std::uint64_t index_pos, std::uint32_t conns, std::uint32_t chunks) {
  const std::size_t h = o.open_length();
  o.field_u8("op", kOpBagHeader);
  o.field_u64("index_pos", index_pos);
  o.field_u32("conn_count", conns);
  o.field_u32("chunk_count", chunks);
  o.close_length(h);
  // The whole record (two lengths, header, padding) is kBagHeaderBytes long.
  const std::size_t header_bytes = o.size() - h;
  o.str(std::string(kBagHeaderBytes - 8 - header_bytes, ' '));
}

/// Stores `samples` as `format` into `out`, as the XTF writer quantises: round half up and
/// clamp to the type's range; non-finite values become 0. Each clamp is counted.
void encode_samples(std::span<const float> samples, std::string_view format, double u16_max,
                    std::uint8_t* out, std::uint64_t& clipped) {
  const double max = format == "u8" ? 255.0 : u16_max;
  const bool f32 = format == "f32";
  const std::size_t bps = format == "u8" ? 1 : (f32 ? 4 : 2);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const float v = samples[k];
    std::uint8_t* o = out + k * bps;
    std::uint32_t q = 0;
    if (!std::isfinite(v)) {
      ++clipped;
    } else if (f32) {
      q = std::bit_cast<std::uint32_t>(v);
    } else {
      const double r = std::floor(static_cast<double>(v) + 0.5);
      if (r < 0.0 || r > max) ++clipped;
      q = r < 0.0 ? 0u : static_cast<std::uint32_t>(std::min(r, max));
    }
    for (std::size_t i = 0; i < bps; ++i) o[i] = static_cast<std::uint8_t>((q >> (8 * i)) & 0xFFu);
  }
}

}  // namespace

std::uint64_t ros_time_ns(UtcTime t, const char* who) {
  const auto us = t.time_since_epoch().count();
  if (us < 0 || us / 1000000 > std::numeric_limits<std::uint32_t>::max()) {
    throw InputError(std::string(who) + ".time_utc = " + std::to_string(us) +
                     " us since 1970: out of range. Violated constraint: a ROS 1 time, "
                     "1970-01-01 <= time < 2106-02-07");
  }
  return static_cast<std::uint64_t>(us) * 1000u;
}

void append_raw_sonar_image(std::vector<std::uint8_t>& out, const SonarPing& p, bool starboard,
                            std::uint64_t time_ns, const WriterOptions& options,
                            std::uint64_t& clipped) {
  const std::vector<float>& samples = starboard ? p.starboard : p.port;
  const std::size_t n = samples.size();
  const std::size_t bps =
      options.sample_format == "u8" ? 1 : (options.sample_format == "f32" ? 4 : 2);
  Out o(out);
  put_header(o, p.ping_number, time_ns, starboard ? kStarboardFrame : kPortFrame);
  // PingInfo
  o.f32(static_cast<float>(options.frequency_hz));
  o.f32(static_cast<float>(p.sound_speed_m_s));
  o.f32_array(options.horizontal_beam_width_rad);
  o.f32_array(options.vertical_beam_width_rad);
  // Two-way travel time to the last sample 2 R / c, n samples over it.
  o.f32(static_cast<float>(static_cast<double>(n) * p.sound_speed_m_s / (2.0 * p.slant_range_m)));
  o.u32(static_cast<std::uint32_t>(n));  // samples_per_beam
  o.u32(0);                              // sample0
  o.f32_array(0.0, true);                // tx_delays
  o.f32_array(0.0, true);                // tx_angles: unsteered, the frame holds the beam axis
  o.f32_array(0.0, true);                // rx_angles
  // SonarImageData
  o.u8(0);  // is_bigendian
  o.u32(options.sample_format == "u8" ? 0u : (options.sample_format == "f32" ? 8u : 2u));
  o.u32(1);  // beam_count
  o.u32(static_cast<std::uint32_t>(n * bps));
  encode_samples(samples, options.sample_format, options.u16_full_range ? 65535.0 : 32767.0,
                 o.take(n * bps).take(n * bps).data(), clipped);
}

void append_side_scan_truth(std::vector<std::uint8_t>& out, const SonarPing& p, bool starboard,
                            std::uint64_t time_ns, const SideOutput& side) {
  Out o(out);
  put_header(o, p.ping_number, time_ns, starboard ? kStarboardFrame : kPortFrame);
  const auto n = static_cast<std::uint32_t>(side.truth_class.size());
  o.u32(n);  // samples
  o.u32(n);
  for (const SampleClass c : side.truth_class) o.u8(static_cast<std::uint8_t>(c));
  o.u32(n);
  for (const std::int32_t v : side.truth_label) o.u32(static_cast<std::uint32_t>(v));
  o.u32(n);
  for (const float v : side.truth_grazing_rad) o.f32(v);
  o.u32(n);
  for (const float v : side.truth_ground_range_m) o.f32(v);
}

void append_nav_sat_fix(std::vector<std::uint8_t>& out, const SonarPing& p, std::uint64_t time_ns) {
  Out o(out);
  put_header(o, p.ping_number, time_ns, kVehicleFrame);
  const bool fix = p.sensor_position.lat_rad != 0.0 || p.sensor_position.lon_rad != 0.0;
  o.i8(fix ? 0 : -1);  // STATUS_FIX or STATUS_NO_FIX
  o.u16(1);            // SERVICE_GPS
  o.f64(deg_from_rad(p.sensor_position.lat_rad));
  o.f64(deg_from_rad(p.sensor_position.lon_rad));
  o.f64(std::numeric_limits<double>::quiet_NaN());  // altitude: not available
  put_covariance(o, 0.0);
  o.u8(0);  // COVARIANCE_TYPE_UNKNOWN
}

void append_imu(std::vector<std::uint8_t>& out, std::uint32_t seq, std::uint64_t time_ns,
                double heading_true_rad, double pitch_rad, double roll_rad) {
  // ENU world, body x forward, y left, z up (REP 103): yaw from east counter-clockwise,
  // pitch + nose down, roll + starboard down.
  const bool known =
      std::isfinite(heading_true_rad) && std::isfinite(pitch_rad) && std::isfinite(roll_rad);
  const Quaternion q =
      known ? quaternion_zyx(std::numbers::pi / 2 - heading_true_rad, -pitch_rad, roll_rad)
            : Quaternion{0, 0, 0, 1};
  Out o(out);
  put_header(o, seq, time_ns, kVehicleFrame);
  put_quaternion(o, q);
  put_covariance(o, known ? 0.0 : -1.0);
  for (int i = 0; i < 3; ++i) o.f64(0.0);  // angular_velocity: none
  put_covariance(o, -1.0);
  for (int i = 0; i < 3; ++i) o.f64(0.0);  // linear_acceleration: none
  put_covariance(o, -1.0);
}

void append_tf_static(std::vector<std::uint8_t>& out, std::uint64_t time_ns, double tilt_rad) {
  Out o(out);
  o.u32(2);
  for (const auto& [frame, yaw] : {std::pair{kPortFrame, std::numbers::pi / 2},
                                   std::pair{kStarboardFrame, -std::numbers::pi / 2}}) {
    put_header(o, 0, time_ns, kVehicleFrame);
    o.str(frame);
    for (int i = 0; i < 3; ++i) o.f64(0.0);  // at the vehicle's reference point
    put_quaternion(o, quaternion_zyx(yaw, tilt_rad, 0.0));
  }
}

void WriterOptions::validate() const {
  const auto bad = [](const std::string& field, double v, const char* constraint) {
    throw InputError("rosbag writer: " + field + " = " + std::to_string(v) +
                     ". Violated constraint: " + constraint);
  };
  if (sample_format != "u16" && sample_format != "u8" && sample_format != "f32") {
    throw InputError("rosbag writer: sample_format = '" + sample_format +
                     "'. Violated constraint: one of u16, u8, f32");
  }
  if (!(frequency_hz >= 0.0) || !std::isfinite(frequency_hz)) {
    bad("frequency_hz", frequency_hz, "frequency_hz >= 0");
  }
  if (!(horizontal_beam_width_rad >= 0.0 && horizontal_beam_width_rad < std::numbers::pi)) {
    bad("horizontal_beam_width_rad", horizontal_beam_width_rad, "0 <= width < pi");
  }
  if (!(vertical_beam_width_rad >= 0.0 && vertical_beam_width_rad < std::numbers::pi)) {
    bad("vertical_beam_width_rad", vertical_beam_width_rad, "0 <= width < pi");
  }
  if (!(tilt_rad >= 0.0 && tilt_rad <= std::numbers::pi / 2)) {
    bad("tilt_rad", tilt_rad, "0 <= tilt_rad <= pi/2");
  }
  if (chunk_bytes < 1) bad("chunk_bytes", 0.0, "chunk_bytes >= 1");
}

Writer::Writer(std::filesystem::path path, WriterOptions options)
    : SonarFileWriter(std::move(path), options.overwrite), options_(std::move(options)) {
  options_.validate();
  out_.open(output_.temp_path(), std::ios::binary | std::ios::trunc);
  if (!out_) throw FormatError("rosbag: cannot create " + output_.temp_path().string());
  connection_written_.assign(kConnCount, false);
  chunk_.reserve(options_.chunk_bytes + (1u << 20));
  record_.clear();
  Out o(record_);
  o.raw(kMagic);
  put_bag_header(o, 0, 0, 0);  // rewritten by close()
  write_file(record_);
}

Writer::~Writer() = default;  // AtomicOutput removes an uncommitted temporary file

void Writer::write_file(const std::vector<std::uint8_t>& bytes) {
  out_.write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  if (!out_) throw FormatError("rosbag: write to " + output_.temp_path().string() + " failed");
  bytes_written_ += bytes.size();
}

void Writer::begin_message(std::uint32_t conn, std::uint64_t time_ns) {
  Out o(chunk_);
  if (!connection_written_[conn]) {
    put_connection(o, conn);
    connection_written_[conn] = true;
  }
  entries_.push_back({conn, time_ns, static_cast<std::uint32_t>(chunk_.size())});
  const std::size_t h = o.open_length();
  o.field_u8("op", kOpMessageData);
  o.field_u32("conn", conn);
  o.field_time("time", time_ns);
  o.close_length(h);
  message_start_ = o.open_length();
}

void Writer::end_message() {
  Out(chunk_).close_length(message_start_);
  if (chunk_.size() >= options_.chunk_bytes) flush_chunk();
}

void Writer::write_side(std::uint32_t conn, const SonarPing& p, std::uint64_t time_ns) {
  begin_message(conn, time_ns);
  append_raw_sonar_image(chunk_, p, conn == kStarboard, time_ns, options_, clipped_samples_);
  end_message();
}

void Writer::write_imu(std::uint64_t time_ns, std::uint32_t seq, double heading_true_rad,
                       double pitch_rad, double roll_rad) {
  begin_message(kImu, time_ns);
  append_imu(chunk_, seq, time_ns, heading_true_rad, pitch_rad, roll_rad);
  end_message();
}

void Writer::write_tf_static(std::uint64_t time_ns) {
  begin_message(kTfStatic, time_ns);
  append_tf_static(chunk_, time_ns, options_.tilt_rad);
  end_message();
  tf_written_ = true;
}

void Writer::write_ping(const SonarPing& p) {
  if (closed_) throw Error("rosbag: write_ping after close");
  const std::uint64_t ns = ros_time_ns(p.time_utc, "ping");
  for (const auto* side : {&p.port, &p.starboard}) {
    if (side->empty()) {
      throw InputError(std::string("ping.") + (side == &p.port ? "port" : "starboard") +
                       ".size() = 0. Violated constraint: >= 1 sample per side");
    }
  }
  if (!(p.slant_range_m > 0.0) || !(p.sound_speed_m_s > 0.0)) {
    throw InputError("ping.slant_range_m = " + std::to_string(p.slant_range_m) +
                     ", ping.sound_speed_m_s = " + std::to_string(p.sound_speed_m_s) +
                     ". Violated constraint: both > 0");
  }
  if (!tf_written_) write_tf_static(ns);
  write_side(kPort, p, ns);
  write_side(kStarboard, p, ns);
  begin_message(kFix, ns);
  append_nav_sat_fix(chunk_, p, ns);
  end_message();
  write_imu(ns, imu_seq_++, p.heading_true_rad, p.pitch_rad, p.roll_rad);
  ++pings_written_;
}

std::optional<std::string> truth_violation(const SideOutput& port, const SideOutput& starboard) {
  for (const SideOutput* side : {&port, &starboard}) {
    const std::string name = side == &port ? "truth.port" : "truth.starboard";
    const std::size_t n = side->truth_class.size();
    if (n == 0)
      return name + ".truth_class.size() = 0. Violated constraint: the ping rendered with truth";
    for (const auto& [field, size] :
         {std::pair{".truth_label", side->truth_label.size()},
          std::pair{".truth_grazing_rad", side->truth_grazing_rad.size()},
          std::pair{".truth_ground_range_m", side->truth_ground_range_m.size()}}) {
      if (size != n) {
        return name + field + ".size() = " + std::to_string(size) +
               ". Violated constraint: as truth_class's (" + std::to_string(n) + ")";
      }
    }
  }
  return std::nullopt;
}

void Writer::write_truth(const SonarPing& p, const SideOutput& port, const SideOutput& starboard) {
  if (closed_) throw Error("rosbag: write_truth after close");
  const std::uint64_t ns = ros_time_ns(p.time_utc, "ping");
  if (const auto v = truth_violation(port, starboard)) throw InputError("rosbag writer: " + *v);
  begin_message(kPortTruth, ns);
  append_side_scan_truth(chunk_, p, false, ns, port);
  end_message();
  begin_message(kStarboardTruth, ns);
  append_side_scan_truth(chunk_, p, true, ns, starboard);
  end_message();
}

void Writer::write_attitude(const AttitudeSample& a) {
  if (closed_) throw Error("rosbag: write_attitude after close");
  write_imu(ros_time_ns(a.time_utc, "attitude"), imu_seq_++, a.heading_true_rad, a.pitch_rad,
            a.roll_rad);
}

void Writer::flush_chunk() {
  if (entries_.empty()) return;
  ChunkInfo info{bytes_written_, entries_.front().time_ns, entries_.front().time_ns,
                 std::vector<std::uint32_t>(kConnCount, 0)};
  for (const ChunkEntry& e : entries_) {
    info.start_ns = std::min(info.start_ns, e.time_ns);
    info.end_ns = std::max(info.end_ns, e.time_ns);
    ++info.counts[e.conn];
  }
  record_.clear();
  Out o(record_);
  const std::size_t h = o.open_length();
  o.field_u8("op", kOpChunk);
  o.field_str("compression", "none");
  o.field_u32("size", static_cast<std::uint32_t>(chunk_.size()));
  o.close_length(h);
  o.u32(static_cast<std::uint32_t>(chunk_.size()));
  write_file(record_);
  write_file(chunk_);
  // One index data record per connection of the chunk: time and offset in the chunk data.
  record_.clear();
  for (std::uint32_t c = 0; c < kConnCount; ++c) {
    if (info.counts[c] == 0) continue;
    const std::size_t ih = o.open_length();
    o.field_u8("op", kOpIndexData);
    o.field_u32("ver", 1);
    o.field_u32("conn", c);
    o.field_u32("count", info.counts[c]);
    o.close_length(ih);
    const std::size_t d = o.open_length();
    for (const ChunkEntry& e : entries_) {
      if (e.conn != c) continue;
      o.time(e.time_ns);
      o.u32(e.offset);
    }
    o.close_length(d);
  }
  write_file(record_);
  chunks_.push_back(std::move(info));
  chunk_.clear();
  entries_.clear();
}

void Writer::close() {
  if (closed_) return;
  flush_chunk();
  const std::uint64_t index_pos = bytes_written_;
  record_.clear();
  Out o(record_);
  std::uint32_t conns = 0;
  for (std::uint32_t c = 0; c < kConnCount; ++c) {
    if (!connection_written_[c]) continue;
    put_connection(o, c);
    ++conns;
  }
  for (const ChunkInfo& ci : chunks_) {
    std::uint32_t present = 0;
    for (std::uint32_t n : ci.counts) present += n > 0 ? 1u : 0u;
    const std::size_t h = o.open_length();
    o.field_u8("op", kOpChunkInfo);
    o.field_u32("ver", 1);
    o.field_u64("chunk_pos", ci.pos);
    o.field_time("start_time", ci.start_ns);
    o.field_time("end_time", ci.end_ns);
    o.field_u32("count", present);
    o.close_length(h);
    const std::size_t d = o.open_length();
    for (std::uint32_t c = 0; c < kConnCount; ++c) {
      if (ci.counts[c] == 0) continue;
      o.u32(c);
      o.u32(ci.counts[c]);
    }
    o.close_length(d);
  }
  write_file(record_);
  record_.clear();
  put_bag_header(o, index_pos, conns, static_cast<std::uint32_t>(chunks_.size()));
  out_.seekp(static_cast<std::streamoff>(kMagic.size()));
  out_.write(reinterpret_cast<const char*>(record_.data()),
             static_cast<std::streamsize>(record_.size()));
  out_.close();
  if (!out_) throw FormatError("rosbag: cannot finish " + output_.temp_path().string());
  output_.commit();
  closed_ = true;
}

}  // namespace sonarsynth::rosbag
