// SPDX-License-Identifier: MIT
// The MCAP container (docs/robotics.md, "File layout"): records, chunks, indexes, summary.
#include "sonarsynth/formats/mcap/writer.hpp"

#include <zlib.h>
#include <zstd.h>

#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <tuple>
#include <utility>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/mcap/opcodes.hpp"
#include "sonarsynth/formats/mcap/ros2_messages.hpp"
#include "sonarsynth/formats/rosbag/message_bytes.hpp"

namespace sonarsynth::mcap {
namespace {

/// One record appended to `out`: opcode, u64 content length (set by the destructor), content
/// little endian, field by field.
class Record {
 public:
  Record(std::vector<std::uint8_t>& out, Opcode op) : out_(out), start_(out.size()) {
    out_.push_back(op);
    u64(0);
  }
  ~Record() {
    const std::uint64_t n = out_.size() - start_ - 9;
    for (std::size_t i = 0; i < 8; ++i) {
      out_[start_ + 1 + i] = static_cast<std::uint8_t>((n >> (8 * i)) & 0xFFu);
    }
  }
  Record(const Record&) = delete;
  Record& operator=(const Record&) = delete;

  void u8(std::uint8_t v) { put(v, 1); }
  void u16(std::uint16_t v) { put(v, 2); }
  void u32(std::uint32_t v) { put(v, 4); }
  void u64(std::uint64_t v) { put(v, 8); }
  void str(std::string_view s) {
    u32(static_cast<std::uint32_t>(s.size()));
    out_.insert(out_.end(), s.begin(), s.end());
  }
  void bytes(std::span<const std::uint8_t> b) { out_.insert(out_.end(), b.begin(), b.end()); }
  std::size_t size() const { return out_.size() - start_; }

 private:
  void put(std::uint64_t v, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      out_.push_back(static_cast<std::uint8_t>((v >> (8 * i)) & 0xFFu));
    }
  }
  std::vector<std::uint8_t>& out_;
  std::size_t start_;
};

struct ChannelDef {
  std::uint16_t id;
  std::uint16_t schema_id;
  std::string_view topic;
};
// The two truth channels (and their schema 5) only in a bag written with WriterOptions::truth.
constexpr std::array<ChannelDef, 7> kChannelDefs = {{
    {1, 1, kPortTopic},
    {2, 1, kStarboardTopic},
    {3, 2, kNavSatTopic},
    {4, 3, kImuTopic},
    {5, 4, kTfStaticTopic},
    {6, 5, kPortTruthTopic},
    {7, 5, kStarboardTruthTopic},
}};
constexpr std::uint16_t kPortChannel = 1, kStarboardChannel = 2, kNavChannel = 3, kImuChannel = 4,
                        kTfChannel = 5, kPortTruthChannel = 6, kStarboardTruthChannel = 7;
constexpr std::uint16_t kBaseChannels = 5, kBaseSchemas = 4;

/// rosbag2's QoS of /tf_static (transient local, so that a late subscriber gets the TF).
constexpr std::string_view kTfStaticQos =
    "- history: 3\n  depth: 0\n  reliability: 1\n  durability: 1\n"
    "  deadline:\n    sec: 2147483647\n    nsec: 4294967295\n"
    "  lifespan:\n    sec: 2147483647\n    nsec: 4294967295\n"
    "  liveliness: 1\n  liveliness_lease_duration:\n    sec: 2147483647\n    nsec: 4294967295\n"
    "  avoid_ros_namespace_conventions: false\n";

const Ros2MessageType& schema_type(std::uint16_t id) {
  switch (id) {
    case 1:
      return raw_sonar_image_type();
    case 2:
      return nav_sat_fix_type();
    case 3:
      return imu_type();
    case 5:
      return side_scan_truth_type();
    default:
      return tf_message_type();
  }
}

/// The Schema records then the Channel records (four and five, one and two more with the truth
/// topics); returns the two groups' lengths.
std::pair<std::uint64_t, std::uint64_t> write_schemas_and_channels(std::vector<std::uint8_t>& out,
                                                                   bool truth) {
  const std::size_t begin = out.size();
  for (std::uint16_t id = 1; id <= kBaseSchemas + (truth ? 1 : 0); ++id) {
    const Ros2MessageType& t = schema_type(id);
    Record r(out, kSchema);
    r.u16(id);
    r.str(t.name);
    r.str("ros2msg");
    r.str(t.definition);  // data: u32 length + bytes, as a string
  }
  const std::size_t middle = out.size();
  for (const ChannelDef& c : kChannelDefs) {
    if (c.id > kBaseChannels && !truth) break;
    Record r(out, kChannel);
    r.u16(c.id);
    r.u16(c.schema_id);
    r.str(c.topic);
    r.str("cdr");
    if (c.id == kTfChannel) {
      constexpr std::string_view key = "offered_qos_profiles";
      r.u32(static_cast<std::uint32_t>(4 + key.size() + 4 + kTfStaticQos.size()));
      r.str(key);
      r.str(kTfStaticQos);
    } else {
      r.u32(0);  // empty metadata map
    }
  }
  return {middle - begin, out.size() - middle};
}

/// The samples as the XTF writer stores them: integers rounded half up and clamped to
/// [0, max], non-finite values 0, each such value counted in `clipped`; float32 as given
/// (non-finite values 0, counted). In floats, t = v + 0.5 is exact for |v| < 2^23 and every
/// larger value clamps; for t in [0, max + 1) truncation is the XTF writer's floor(v + 0.5), so
/// the values are the same. Branch-free loops, one per encoding.
void encode_samples(std::span<const float> in, xtf::SampleEncoding e, std::uint8_t* o,
                    std::uint64_t& clipped) {
  std::uint64_t bad = 0;
  const auto quantise = [&bad](float v, float max) {
    const bool finite = std::abs(v) <= std::numeric_limits<float>::max();
    const float t = v + 0.5f;
    bad += (finite && t >= 0.0f && t < max + 1.0f) ? 0u : 1u;
    const float c = finite ? std::min(std::max(t, 0.0f), max) : 0.0f;
    return static_cast<std::uint32_t>(static_cast<std::int32_t>(c));
  };
  const std::size_t n = in.size();
  if (e == xtf::SampleEncoding::kUint16) {
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t q = quantise(in[k], 32767.0f);
      o[2 * k] = static_cast<std::uint8_t>(q & 0xFFu);
      o[2 * k + 1] = static_cast<std::uint8_t>(q >> 8);
    }
  } else if (e == xtf::SampleEncoding::kUint8) {
    for (std::size_t k = 0; k < n; ++k) o[k] = static_cast<std::uint8_t>(quantise(in[k], 255.0f));
  } else {
    for (std::size_t k = 0; k < n; ++k) {
      const float v = in[k];
      const bool finite = std::abs(v) <= std::numeric_limits<float>::max();
      bad += finite ? 0u : 1u;
      const std::uint32_t bits = finite ? std::bit_cast<std::uint32_t>(v) : 0u;
      for (std::size_t i = 0; i < 4; ++i) {
        o[4 * k + i] = static_cast<std::uint8_t>((bits >> (8 * i)) & 0xFFu);
      }
    }
  }
  clipped += bad;
}

[[noreturn]] void violated(const std::string& field, const std::string& value,
                           const std::string& constraint) {
  throw InputError("mcap writer: " + field + " = " + value +
                   ". Violated constraint: " + constraint);
}

}  // namespace

struct Writer::ChunkIndex {
  std::uint64_t start_ns, end_ns, offset, length;
  std::array<std::uint64_t, kChannels> index_offset;  // 0 = no messages of the channel
  std::uint64_t index_length, compressed, uncompressed;
};

struct Writer::Zstd {
  ZSTD_CCtx* cctx = ZSTD_createCCtx();
  ~Zstd() { ZSTD_freeCCtx(cctx); }
};

void WriterOptions::validate() const {
  if (!(frequency_hz > 0.0) || !std::isfinite(frequency_hz)) {
    violated("frequency_hz", std::to_string(frequency_hz), "finite and > 0");
  }
  for (const auto& [name, v] : {std::pair{"horizontal_beam_width_rad", horizontal_beam_width_rad},
                                std::pair{"vertical_beam_width_rad", vertical_beam_width_rad}}) {
    if (!(v >= 0.0 && v < kPi)) violated(name, std::to_string(v), "in [0, pi)");
  }
  if (!(std::abs(tilt_rad) <= kPi / 2)) {
    violated("tilt_rad", std::to_string(tilt_rad), "in [-pi/2, pi/2]");
  }
  if (chunk_bytes < 1024 || chunk_bytes > (std::size_t{1} << 30)) {
    violated("chunk_bytes", std::to_string(chunk_bytes), "in [1024, 2^30]");
  }
  if (zstd_level < 1 || zstd_level > 19) {
    violated("zstd_level", std::to_string(zstd_level), "in [1, 19]");
  }
}

Writer::Writer(std::filesystem::path path, WriterOptions options)
    : SonarFileWriter((options.validate(), std::move(path)), options.overwrite),
      options_(std::move(options)),
      stream_buffer_(std::size_t{1} << 20),
      zstd_(std::make_unique<Zstd>()) {
  if (!zstd_->cctx) throw FormatError("mcap writer: cannot create a zstd context");
  out_.rdbuf()->pubsetbuf(stream_buffer_.data(),
                          static_cast<std::streamsize>(stream_buffer_.size()));
  out_.open(output_.temp_path(), std::ios::binary | std::ios::trunc);
  if (!out_) {
    throw FormatError("mcap writer: cannot create " + output_.temp_path().string() + ": " +
                      std::strerror(errno));
  }
  data_crc_ = static_cast<std::uint32_t>(crc32_z(0L, Z_NULL, 0));
  write_start();
}

Writer::~Writer() {
  if (!closed_ && out_.is_open()) out_.close();
}

void Writer::emit(const std::vector<std::uint8_t>& bytes, bool data_section) {
  out_.write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  if (!out_) {
    throw FormatError("mcap writer: write failed at byte " + std::to_string(bytes_written_) +
                      " of " + output_.temp_path().string() + ": " + std::strerror(errno));
  }
  if (data_section)
    data_crc_ = static_cast<std::uint32_t>(crc32_z(data_crc_, bytes.data(), bytes.size()));
  bytes_written_ += bytes.size();
}

void Writer::write_start() {
  record_.assign(kMagic.begin(), kMagic.end());
  {
    Record r(record_, kHeader);
    r.str("ros2");
    r.str("sonarsynth");
  }
  write_schemas_and_channels(record_, options_.truth);
  emit(record_, true);
}

void Writer::add_message(std::uint16_t channel, std::uint64_t time_ns) {
  const std::size_t c = channel - 1u;
  if (chunk_.empty()) {
    chunk_start_ns_ = time_ns;
    chunk_end_ns_ = time_ns;
  }
  chunk_start_ns_ = std::min(chunk_start_ns_, time_ns);
  chunk_end_ns_ = std::max(chunk_end_ns_, time_ns);
  if (messages_written_ == 0) start_ns_ = end_ns_ = time_ns;
  start_ns_ = std::min(start_ns_, time_ns);
  end_ns_ = std::max(end_ns_, time_ns);
  index_[c].emplace_back(time_ns, chunk_.size());
  {
    Record r(chunk_, kMessage);
    r.u16(channel);
    r.u32(sequence_[c]++);
    r.u64(time_ns);  // log_time
    r.u64(time_ns);  // publish_time
    r.bytes(message_);
  }
  ++channel_messages_[c];
  ++messages_written_;
}

void Writer::write_side(std::uint16_t channel, const SonarPing& p,
                        const std::vector<float>& samples, std::int32_t sec,
                        std::uint32_t nanosec) {
  RawSonarImageFields f;
  f.header = {sec, nanosec, channel == kPortChannel ? kPortFrame : kStarboardFrame};
  f.frequency_hz = static_cast<float>(options_.frequency_hz);
  f.sound_speed_m_s = static_cast<float>(p.sound_speed_m_s);
  f.tx_beamwidth_rad = static_cast<float>(options_.horizontal_beam_width_rad);
  f.rx_beamwidth_rad = static_cast<float>(options_.vertical_beam_width_rad);
  const double n = static_cast<double>(samples.size());
  // Sample i covers slant range [i, i+1) R / n: two-way time 2 R / c over n samples.
  f.sample_rate_hz = static_cast<float>(n * p.sound_speed_m_s / (2.0 * p.slant_range_m));
  f.samples = static_cast<std::uint32_t>(samples.size());
  const xtf::SampleEncoding e = options_.sample_encoding;
  f.dtype = e == xtf::SampleEncoding::kUint16  ? SonarImageDtype::kUint16
            : e == xtf::SampleEncoding::kUint8 ? SonarImageDtype::kUint8
                                               : SonarImageDtype::kFloat32;
  CdrWriter w(message_);
  const std::span<std::uint8_t> out = write_raw_sonar_image(w, f);
  encode_samples(samples, e, out.data(), clipped_samples_);
  const std::uint64_t ns =
      static_cast<std::uint64_t>(sec) * 1'000'000'000u + std::uint64_t{nanosec};
  add_message(channel, ns);
}

Writer::Ros2Time Writer::ros2_time(UtcTime t, const char* field) {
  const std::int64_t us = t.time_since_epoch().count();
  const std::int64_t max_us = std::int64_t{std::numeric_limits<std::int32_t>::max()} * 1'000'000;
  if (us < 0 || us > max_us) {
    violated(field, std::to_string(us) + " us since 1970",
             "from 1970 to 2038-01-19 (builtin_interfaces/Time's int32 seconds)");
  }
  return {static_cast<std::int32_t>(us / 1'000'000),
          static_cast<std::uint32_t>((us % 1'000'000) * 1000),
          static_cast<std::uint64_t>(us) * 1000u};
}

void Writer::write_imu_message(std::int32_t sec, std::uint32_t nanosec, std::uint64_t ns,
                               double heading_true_rad, double pitch_rad, double roll_rad) {
  // ENU world, FLU body (REP 103): yaw from east counter-clockwise; + pitch is nose down.
  CdrWriter w(message_);
  write_imu(w, {sec, nanosec, kBodyFrame},
            rosbag::quaternion_zyx(kPi / 2 - heading_true_rad, -pitch_rad, roll_rad));
  add_message(kImuChannel, ns);
}

void Writer::write_attitude(const AttitudeSample& a) {
  if (closed_) throw FormatError("mcap writer: " + path().string() + " is already closed");
  for (const auto& [name, v] : {std::pair{"attitude.heading_true_rad", a.heading_true_rad},
                                {"attitude.pitch_rad", a.pitch_rad},
                                {"attitude.roll_rad", a.roll_rad}}) {
    if (!std::isfinite(v)) violated(name, std::to_string(v), "finite");
  }
  const auto [sec, nanosec, ns] = ros2_time(a.time_utc, "attitude.time_utc");
  write_imu_message(sec, nanosec, ns, a.heading_true_rad, a.pitch_rad, a.roll_rad);
  if (chunk_.size() >= options_.chunk_bytes) flush_chunk();
}

void Writer::write_ping(const SonarPing& p) {
  if (closed_) throw FormatError("mcap writer: " + path().string() + " is already closed");
  if (p.port.empty()) violated("ping.port.size()", "0", "port.size() >= 1");
  if (p.starboard.empty()) violated("ping.starboard.size()", "0", "starboard.size() >= 1");
  if (!(p.slant_range_m > 0.0) || !std::isfinite(p.slant_range_m)) {
    violated("ping.slant_range_m", std::to_string(p.slant_range_m), "finite and > 0");
  }
  if (!(p.sound_speed_m_s > 0.0) || !std::isfinite(p.sound_speed_m_s)) {
    violated("ping.sound_speed_m_s", std::to_string(p.sound_speed_m_s), "finite and > 0");
  }
  const auto [sec, nanosec, ns] = ros2_time(p.time_utc, "ping.time_utc");

  if (pings_written_ == 0) {
    // The sonar on the vehicle: the navigated point is the transducers' (SonarPing), and each
    // side's frame turns x to its beam axis, depressed by the tilt (docs/robotics.md).
    const double t = options_.tilt_rad;
    const std::array<Transform, 2> tf = {{
        {kBodyFrame, kPortFrame, 0.0, 0.0, 0.0, rosbag::quaternion_zyx(kPi / 2, t, 0.0)},
        {kBodyFrame, kStarboardFrame, 0.0, 0.0, 0.0, rosbag::quaternion_zyx(-kPi / 2, t, 0.0)},
    }};
    CdrWriter w(message_);
    write_tf_message(w, sec, nanosec, tf);
    add_message(kTfChannel, ns);
  }
  {
    CdrWriter w(message_);
    // A position of exactly 0, 0 is "none" (SonarPing), e.g. an XTF ping without navigation.
    const Geodetic& g = p.sensor_position;
    const bool fix = std::isfinite(g.lat_rad) && std::isfinite(g.lon_rad) &&
                     (g.lat_rad != 0.0 || g.lon_rad != 0.0);
    write_nav_sat_fix(w, {sec, nanosec, kBodyFrame}, fix, deg_from_rad(p.sensor_position.lat_rad),
                      deg_from_rad(p.sensor_position.lon_rad),
                      std::numeric_limits<double>::quiet_NaN());
    add_message(kNavChannel, ns);
  }
  write_imu_message(sec, nanosec, ns, p.heading_true_rad, p.pitch_rad, p.roll_rad);
  write_side(kPortChannel, p, p.port, sec, nanosec);
  write_side(kStarboardChannel, p, p.starboard, sec, nanosec);
  ++pings_written_;
  if (chunk_.size() >= options_.chunk_bytes) flush_chunk();
}

void Writer::write_truth(const SonarPing& p, const SideOutput& port, const SideOutput& starboard) {
  if (closed_) throw FormatError("mcap writer: " + path().string() + " is already closed");
  if (!options_.truth) {
    violated("options.truth", "false", "true to write truth (the truth topics are declared first)");
  }
  if (const auto v = rosbag::truth_violation(port, starboard)) {
    throw InputError("mcap writer: " + *v);
  }
  const auto [sec, nanosec, ns] = ros2_time(p.time_utc, "ping.time_utc");
  for (const auto& [side, channel, frame] :
       {std::tuple{&port, kPortTruthChannel, kPortFrame},
        std::tuple{&starboard, kStarboardTruthChannel, kStarboardFrame}}) {
    CdrWriter w(message_);
    write_side_scan_truth(w, {sec, nanosec, frame}, *side);
    add_message(channel, ns);
  }
  if (chunk_.size() >= options_.chunk_bytes) flush_chunk();
}

void Writer::flush_chunk() {
  if (chunk_.empty()) return;
  compressed_.resize(ZSTD_compressBound(chunk_.size()));
  const std::size_t n = ZSTD_compressCCtx(zstd_->cctx, compressed_.data(), compressed_.size(),
                                          chunk_.data(), chunk_.size(), options_.zstd_level);
  if (ZSTD_isError(n)) {
    throw FormatError(std::string("mcap writer: zstd compression failed: ") + ZSTD_getErrorName(n));
  }
  ChunkIndex ci{};
  ci.start_ns = chunk_start_ns_;
  ci.end_ns = chunk_end_ns_;
  ci.offset = bytes_written_;
  ci.compressed = n;
  ci.uncompressed = chunk_.size();
  record_.clear();
  {
    Record r(record_, kChunk);
    r.u64(chunk_start_ns_);
    r.u64(chunk_end_ns_);
    r.u64(chunk_.size());
    r.u32(static_cast<std::uint32_t>(crc32_z(0L, chunk_.data(), chunk_.size())));
    r.str("zstd");
    r.u64(n);
    r.bytes(std::span<const std::uint8_t>(compressed_.data(), n));
  }
  ci.length = record_.size();
  for (std::size_t c = 0; c < kChannels; ++c) {
    if (index_[c].empty()) continue;
    ci.index_offset[c] = ci.offset + record_.size();
    Record r(record_, kMessageIndex);
    r.u16(static_cast<std::uint16_t>(c + 1));
    r.u32(static_cast<std::uint32_t>(index_[c].size() * 16));
    for (const auto& [time_ns, offset] : index_[c]) {
      r.u64(time_ns);
      r.u64(offset);
    }
    index_[c].clear();
  }
  ci.index_length = record_.size() - ci.length;
  emit(record_, true);
  chunk_indexes_.push_back(ci);
  chunk_.clear();
}

void Writer::write_summary() {
  record_.clear();
  {
    Record r(record_, kDataEnd);
    r.u32(data_crc_);
  }
  emit(record_, false);
  const std::uint64_t summary_start = bytes_written_;
  record_.clear();
  const auto [schemas_length, channels_length] =
      write_schemas_and_channels(record_, options_.truth);
  const std::size_t channels = kBaseChannels + (options_.truth ? 2u : 0u);
  const std::size_t statistics_at = record_.size();
  {
    Record r(record_, kStatistics);
    r.u64(messages_written_);
    r.u16(static_cast<std::uint16_t>(kBaseSchemas + (options_.truth ? 1 : 0)));
    r.u32(static_cast<std::uint32_t>(channels));
    r.u32(0);  // attachments
    r.u32(0);  // metadata
    r.u32(static_cast<std::uint32_t>(chunk_indexes_.size()));
    r.u64(start_ns_);
    r.u64(end_ns_);
    r.u32(static_cast<std::uint32_t>(channels * 10));
    for (std::size_t c = 0; c < channels; ++c) {
      r.u16(static_cast<std::uint16_t>(c + 1));
      r.u64(channel_messages_[c]);
    }
  }
  const std::size_t chunk_indexes_at = record_.size();
  for (const ChunkIndex& ci : chunk_indexes_) {
    Record r(record_, kChunkIndex);
    r.u64(ci.start_ns);
    r.u64(ci.end_ns);
    r.u64(ci.offset);
    r.u64(ci.length);
    std::uint32_t entries = 0;
    for (const std::uint64_t o : ci.index_offset) entries += o != 0 ? 1u : 0u;
    r.u32(entries * 10);
    for (std::size_t c = 0; c < kChannels; ++c) {
      if (ci.index_offset[c] == 0) continue;
      r.u16(static_cast<std::uint16_t>(c + 1));
      r.u64(ci.index_offset[c]);
    }
    r.u64(ci.index_length);
    r.str("zstd");
    r.u64(ci.compressed);
    r.u64(ci.uncompressed);
  }
  const std::uint64_t summary_offset_start = summary_start + record_.size();
  const struct {
    Opcode op;
    std::uint64_t start, length;
  } groups[] = {
      {kSchema, summary_start, schemas_length},
      {kChannel, summary_start + schemas_length, channels_length},
      {kStatistics, summary_start + statistics_at, chunk_indexes_at - statistics_at},
      {kChunkIndex, summary_start + chunk_indexes_at,
       summary_offset_start - summary_start - chunk_indexes_at},
  };
  for (const auto& g : groups) {
    if (g.length == 0) continue;
    Record r(record_, kSummaryOffset);
    r.u8(g.op);
    r.u64(g.start);
    r.u64(g.length);
  }
  // Footer: the summary CRC covers the summary, the summary offsets and the footer up to the
  // CRC field itself.
  record_.push_back(kFooter);
  for (const std::uint64_t v : {std::uint64_t{20}, summary_start, summary_offset_start}) {
    for (std::size_t i = 0; i < 8; ++i) record_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  const auto crc = static_cast<std::uint32_t>(crc32_z(0L, record_.data(), record_.size()));
  for (std::size_t i = 0; i < 4; ++i) record_.push_back(static_cast<std::uint8_t>(crc >> (8 * i)));
  record_.insert(record_.end(), kMagic.begin(), kMagic.end());
  emit(record_, false);
}

void Writer::close() {
  if (closed_) return;
  flush_chunk();
  write_summary();
  out_.flush();
  if (!out_) {
    throw FormatError("mcap writer: flush failed for " + output_.temp_path().string() + ": " +
                      std::strerror(errno));
  }
  out_.close();
  if (out_.fail())
    throw FormatError("mcap writer: close failed for " + output_.temp_path().string());
  closed_ = true;
  output_.commit();
}

}  // namespace sonarsynth::mcap
