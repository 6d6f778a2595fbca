// SPDX-License-Identifier: MIT
// ROS 1 bag reader, format 2.0 (docs/rosbag.md, "Reading bags"): the index, uncompressed
// chunks, and the writer's message mapping reversed.
#include "sonarsynth/formats/rosbag/reader.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <string_view>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/rosbag/bag_records.hpp"
#include "sonarsynth/formats/rosbag/messages.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::rosbag {
namespace {

constexpr std::string_view kMagic = "#ROSBAG V2.0\n";
constexpr std::uint8_t kOpMessageData = 0x02;
constexpr std::uint8_t kOpBagHeader = 0x03;
constexpr std::uint8_t kOpChunk = 0x05;
constexpr std::uint8_t kOpChunkInfo = 0x06;
constexpr std::uint8_t kOpConnection = 0x07;
constexpr std::size_t kMaxPending = 4096;  // unpaired image stamps kept before giving up on one

constexpr std::string_view kImageType = "marine_acoustic_msgs/RawSonarImage";
constexpr std::string_view kFixType = "sensor_msgs/NavSatFix";
constexpr std::string_view kImuType = "sensor_msgs/Imu";
constexpr std::string_view kTfType = "tf2_msgs/TFMessage";

using records::attitude_from_quaternion;
using records::Cursor;
using records::decode_samples;
using records::fail;
using records::field;
using records::field_str;
using records::field_uint;
using records::Fields;
using records::kDtypeBytes;
using records::le;
using records::parse_fields;
using records::parse_record;
using records::Record;

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

/// +1 port, -1 starboard, 0 neither: from the frame id, else from the topic (docs/rosbag.md).
int side_of(std::string_view frame, std::string_view topic) {
  for (const std::string& s : {lower(frame), lower(topic)}) {
    if (s.find("port") != std::string::npos) return 1;
    if (s.find("starboard") != std::string::npos || s.find("stbd") != std::string::npos) return -1;
  }
  return 0;
}

UtcTime utc_from_ns(std::uint64_t ns) {
  return UtcTime{std::chrono::microseconds{static_cast<std::int64_t>(ns / 1000u)}};
}

/// The element of `v` (sorted by stamp, ordinal) with the latest stamp <= `stamp`; of several
/// with that stamp the first written after `ordinal` (the writer puts a ping's navigation after
/// its images), else the last.
template <class T>
T* at_or_before(std::vector<T>& v, std::uint64_t stamp, std::uint64_t ordinal) {
  auto it = std::upper_bound(v.begin(), v.end(), stamp,
                             [](std::uint64_t s, const T& e) { return s < e.stamp_ns; });
  if (it == v.begin()) return nullptr;
  const std::uint64_t s = std::prev(it)->stamp_ns;
  auto k = std::lower_bound(v.begin(), it, s,
                            [](const T& e, std::uint64_t t) { return e.stamp_ns < t; });
  for (; k != it; ++k) {
    if (k->ordinal > ordinal) return &*k;
  }
  return &*std::prev(it);
}

}  // namespace

Reader::Reader(const std::filesystem::path& path) : Reader(xtf::open_file_source(path)) {}

Reader::Reader(std::span<const std::uint8_t> bytes, std::string name)
    : Reader(xtf::memory_source(bytes, std::move(name))) {}

Reader::Reader(std::unique_ptr<xtf::ByteSource> source) : source_(std::move(source)) {
  open();
}

Reader::~Reader() = default;

const std::string& Reader::name() const {
  return source_->name();
}

void Reader::report(std::uint64_t offset, std::string message) {
  ++anomaly_count_;
  if (anomalies_.size() < 1000) anomalies_.push_back({offset, std::move(message)});
}

void Reader::open() {
  size_ = source_->size();
  std::array<std::uint8_t, kMagic.size()> magic{};
  if (size_ >= magic.size()) source_->read(0, magic);
  if (size_ < magic.size() || std::memcmp(magic.data(), kMagic.data(), kMagic.size()) != 0) {
    fail(name(), 0, "not a ROS bag 2.0 (the file does not start with '#ROSBAG V2.0')");
  }
  read_index();
  for (std::size_t k = 0; k < chunks_.size(); ++k) scan_chunk(k, false);
  const auto by_stamp = [](const auto& a, const auto& b) {
    return a.stamp_ns != b.stamp_ns ? a.stamp_ns < b.stamp_ns : a.ordinal < b.ordinal;
  };
  std::sort(fixes_.begin(), fixes_.end(), by_stamp);
  std::sort(imu_.begin(), imu_.end(), by_stamp);
  if (image_info_ && tilt_rad_) image_info_->tilt_rad = *tilt_rad_;
}

void Reader::read_index() {
  const std::string& file = name();
  // The bag header record: its header (without the padding) is enough.
  std::vector<std::uint8_t> head(
      static_cast<std::size_t>(std::min<std::uint64_t>(size_ - kMagic.size(), 4096)));
  source_->read(kMagic.size(), head);
  Record r;
  parse_record(head, 0, kMagic.size(), file, r, false);
  if (r.op != kOpBagHeader) {
    fail(file, r.pos, "op = " + std::to_string(r.op) + ": expected the bag header record (3)");
  }
  const std::uint64_t index_pos = field_uint(r, "index_pos", file, 8);
  const std::uint64_t chunk_count = field_uint(r, "chunk_count", file, 4);
  if (index_pos == 0) fail(file, r.pos, "index_pos = 0: the bag is not indexed (rosbag reindex)");
  if (index_pos < kMagic.size() || index_pos >= size_) {
    fail(file, r.pos,
         "index_pos = " + std::to_string(index_pos) + ": past the end of the " +
             std::to_string(size_) + "-byte file");
  }
  std::vector<std::uint8_t> index(static_cast<std::size_t>(size_ - index_pos));
  source_->read(index_pos, index);
  std::map<std::uint32_t, std::uint64_t> counts;
  for (std::size_t at = 0; at < index.size(); at += r.size) {
    parse_record(index, at, index_pos, file, r);
    if (r.op == kOpConnection) {
      const auto id = static_cast<std::uint32_t>(field_uint(r, "conn", file, 4));
      Fields c;  // the connection header is the record's data
      parse_fields(r.data, r.pos + r.size - r.data.size(), file, c);
      ConnectionInfo info;
      info.id = id;
      info.topic = field_str(r, "topic", file);
      for (const auto& [n, v] : c) {
        const std::string s(reinterpret_cast<const char*>(v.data()), v.size());
        if (n == "type") info.type = s;
        if (n == "md5sum") info.md5sum = s;
      }
      if (info.type.empty())
        fail(file, r.pos, "connection " + std::to_string(id) + ": field 'type' missing");
      Kind kind = Kind::kNone;
      if (info.type == kImageType) kind = Kind::kImage;
      if (info.type == kFixType) kind = Kind::kFix;
      if (info.type == kImuType) kind = Kind::kImu;
      if (info.type == kTfType) kind = Kind::kTf;
      if (kind != Kind::kNone && info.md5sum != "*" && info.md5sum != message_md5(info.type)) {
        report(r.pos, "rosbag reader: " + file + ": connection " + std::to_string(id) + " (" +
                          info.topic + ") md5sum = " + info.md5sum + ": not the " + info.type +
                          " of docs/rosbag.md (" + message_md5(info.type) + "); not read");
        kind = Kind::kNone;
      }
      info.decoded = kind != Kind::kNone;
      if (!by_id_.contains(id)) {
        by_id_[id] = connections_.size();
        connections_.push_back(std::move(info));
        kinds_.push_back(kind);
      }
    } else if (r.op == kOpChunkInfo) {
      chunks_.push_back(field_uint(r, "chunk_pos", file, 8));
      Cursor c(r.data, r.pos + r.size - r.data.size(), file, "chunk info");
      const std::uint64_t n = field_uint(r, "count", file, 4);
      for (std::uint64_t k = 0; k < n; ++k) {
        const std::uint32_t conn = c.u32("conn");
        counts[conn] += c.u32("count");
      }
    } else {
      fail(file, r.pos,
           "op = " + std::to_string(r.op) +
               ": unknown op code in the index (connection 7 or chunk info 6)");
    }
  }
  for (ConnectionInfo& c : connections_) c.messages = counts[c.id];
  if (chunks_.size() != chunk_count) {
    report(index_pos,
           "rosbag reader: " + file + ": bag header chunk_count = " + std::to_string(chunk_count) +
               ", index holds " + std::to_string(chunks_.size()) + " chunk info records");
  }
  std::sort(chunks_.begin(), chunks_.end());
  chunk_ordinal_.assign(chunks_.size(), 0);
}

void Reader::scan_chunk(std::size_t chunk, bool images) {
  const std::string& file = name();
  const std::uint64_t pos = chunks_[chunk];
  if (pos >= size_ || size_ - pos < 8) {
    fail(file, pos,
         "chunk_pos = " + std::to_string(pos) + ": past the end of the " + std::to_string(size_) +
             "-byte file");
  }
  std::array<std::uint8_t, 4> len{};
  source_->read(pos, len);
  const std::uint64_t hlen = le(len.data(), 4);
  if (hlen > size_ - pos - 8) {
    fail(file, pos, "chunk header_len = " + std::to_string(hlen) + ": past the end of the file");
  }
  buffer_.resize(static_cast<std::size_t>(hlen + 8));
  source_->read(pos, buffer_);
  Record r;
  parse_record(buffer_, 0, pos, file, r, false);
  if (r.op != kOpChunk) {
    fail(file, pos, "op = " + std::to_string(r.op) + ": chunk_pos does not point at a chunk (5)");
  }
  const std::string compression = field_str(r, "compression", file);
  if (compression != "none") {
    fail(file, pos,
         "chunk compression = '" + compression +
             "': compressed chunks are not read (only 'none'; rosbag decompress)");
  }
  const std::uint64_t data_pos = pos + 8 + hlen;
  const std::uint64_t dlen = le(buffer_.data() + 4 + hlen, 4);
  if (dlen > size_ - data_pos) {
    fail(file, pos + 4 + hlen,
         "chunk data_len = " + std::to_string(dlen) + ": past the end (" +
             std::to_string(size_ - data_pos) + " bytes left)");
  }
  buffer_.resize(static_cast<std::size_t>(dlen));
  source_->read(data_pos, buffer_);
  std::uint64_t ordinal = chunk_ordinal_[chunk];
  for (std::size_t at = 0; at < buffer_.size(); at += r.size) {
    parse_record(buffer_, at, data_pos, file, r);
    if (r.op == kOpConnection) continue;  // also in the index
    if (r.op != kOpMessageData) {
      fail(file, r.pos,
           "op = " + std::to_string(r.op) +
               ": unknown op code in a chunk (message data 2 or connection 7)");
    }
    const auto conn = static_cast<std::uint32_t>(field_uint(r, "conn", file, 4));
    field(r, "time", file, 8);
    ordinal_ = ordinal++;
    message(conn, r.data, r.pos + r.size - r.data.size(), images);
  }
  if (!images && chunk + 1 < chunks_.size()) chunk_ordinal_[chunk + 1] = ordinal;
}

void Reader::message(std::uint32_t conn, std::span<const std::uint8_t> data, std::uint64_t offset,
                     bool images) {
  const auto it = by_id_.find(conn);
  if (it == by_id_.end()) {
    report(offset, "rosbag reader: " + name() + ": byte " + std::to_string(offset) +
                       ": message of connection " + std::to_string(conn) +
                       ", which the index does not list; skipped");
    return;
  }
  const Kind kind = kinds_[it->second];
  // The constructor's pass reads navigation, attitude and the first image's settings; the
  // pings' pass reads the images.
  if (kind == Kind::kNone) return;
  if (images ? kind != Kind::kImage : kind == Kind::kImage && image_info_) return;
  const ConnectionInfo& info = connections_[it->second];
  Cursor c(data, offset, name(), info.type);
  std::uint32_t seq = 0;
  std::string_view frame;
  try {
    if (kind == Kind::kTf) return transforms(c);
    const std::uint64_t stamp = c.header(seq, frame);
    if (kind == Kind::kFix) {
      Fix f{stamp, ordinal_, {}, false};
      const auto status = static_cast<std::int8_t>(c.u8("status.status"));
      c.take(2, "status.service");
      const double lat = c.f64("latitude"), lon = c.f64("longitude");
      f.valid = status >= 0 && std::abs(lat) <= 90.0 && std::abs(lon) <= 180.0 &&
                (lat != 0.0 || lon != 0.0);
      if (f.valid) {
        f.position = {rad_from_deg(lat), rad_from_deg(lon), 0.0};
      }
      fixes_.push_back(f);
    } else if (kind == Kind::kImu) {
      ImuSample s;
      s.stamp_ns = stamp;
      s.ordinal = ordinal_;
      s.attitude.time_utc = utc_from_ns(stamp);
      const double x = c.f64("orientation.x"), y = c.f64("orientation.y");
      const double z = c.f64("orientation.z"), w = c.f64("orientation.w");
      const double cov0 = c.f64("orientation_covariance");
      s.known = cov0 != -1.0 && attitude_from_quaternion(x, y, z, w, s.attitude);
      imu_.push_back(s);
    } else {
      image(c, seq, stamp, frame, info, offset, images);
    }
  } catch (const FormatError& e) {
    report(offset, e.what());
  }
}

void Reader::transforms(records::Cursor& c) {
  // The writer's port transform: yaw +pi/2, then pitch = tilt about the new y (docs/rosbag.md,
  // "Frames"); the pitch of its ZYX angles is the tilt.
  const std::uint32_t n = c.u32("transforms");
  for (std::uint32_t k = 0; k < n && !tilt_rad_; ++k) {
    std::uint32_t tf_seq = 0;
    std::string_view parent;
    c.header(tf_seq, parent);
    const std::string child = lower(c.str("transforms.child_frame_id"));
    for (int i = 0; i < 3; ++i) c.f64("transforms.transform.translation");
    const double x = c.f64("transforms.transform.rotation.x");
    const double y = c.f64("transforms.transform.rotation.y");
    const double z = c.f64("transforms.transform.rotation.z");
    const double w = c.f64("transforms.transform.rotation.w");
    AttitudeSample a;
    if (child.find("port") != std::string::npos && attitude_from_quaternion(x, y, z, w, a) &&
        a.pitch_rad <= 0.0) {
      tilt_rad_ = -a.pitch_rad;  // attitude_from_quaternion gives -pitch (nose up)
    }
  }
}

void Reader::image(Cursor& c, std::uint32_t seq, std::uint64_t stamp, std::string_view frame,
                   const ConnectionInfo& info, std::uint64_t offset, bool images) {
  Side side;
  side.offset = offset;
  side.ordinal = ordinal_;
  side.seq = seq;
  ImageInfo ii;
  ii.frequency_hz = static_cast<double>(c.f32("ping_info.frequency"));
  side.sound_speed_m_s = static_cast<double>(c.f32("ping_info.sound_speed"));
  ii.horizontal_beam_width_rad = c.first_f32("ping_info.tx_beamwidths");
  ii.vertical_beam_width_rad = c.first_f32("ping_info.rx_beamwidths");
  const double rate = static_cast<double>(c.f32("sample_rate"));
  const std::uint32_t n = c.u32("samples_per_beam");
  c.u32("sample0");
  c.first_f32("tx_delays");
  c.first_f32("tx_angles");
  c.first_f32("rx_angles");
  const bool big = c.u8("image.is_bigendian") != 0;
  ii.dtype = side.dtype = c.u32("image.dtype");
  const std::uint32_t beams = c.u32("image.beam_count");
  const auto bytes = c.take(c.u32("image.data"), "image.data");
  if (!image_info_) image_info_ = ii;
  if (!images) return;
  const std::string where = "rosbag reader: " + name() + ": byte " + std::to_string(offset) + ": ";
  const auto bad = [&](const std::string& what) {
    report(offset, where + info.type + " (" + info.topic + ") " + what + "; skipped");
  };
  if (side.dtype >= kDtypeBytes.size()) {
    return bad("image.dtype = " + std::to_string(side.dtype) + ": unknown (0..9)");
  }
  if (beams != 1) {
    return bad("image.beam_count = " + std::to_string(beams) + ": one beam per side expected");
  }
  if (n == 0 || bytes.size() != std::size_t{n} * kDtypeBytes[side.dtype]) {
    return bad("image.data has " + std::to_string(bytes.size()) +
               " bytes for samples_per_beam = " + std::to_string(n));
  }
  if (!(rate > 0.0) || !std::isfinite(rate)) {
    return bad("sample_rate = " + std::to_string(rate) + ": not > 0");
  }
  const int which = side_of(frame, info.topic);
  if (which == 0) {
    return bad("header.frame_id = '" + std::string(frame) +
               "': neither port nor starboard (frame id or topic)");
  }
  if (!(side.sound_speed_m_s > 0.0) || !std::isfinite(side.sound_speed_m_s)) {
    report(offset, where + "ping_info.sound_speed = " + std::to_string(side.sound_speed_m_s) +
                       ": 1500 m/s assumed");
    side.sound_speed_m_s = 1500.0;
  }
  side.slant_range_m = n * side.sound_speed_m_s / (2.0 * rate);
  decode_samples(bytes, side.dtype, big, side.samples);
  side.present = true;
  add_side(std::move(side), which > 0, stamp);
}

void Reader::add_side(Side side, bool port, std::uint64_t stamp_ns) {
  auto& pair = pending_[stamp_ns];
  Side& slot = port ? pair.first : pair.second;
  if (slot.present) {
    report(slot.offset, "rosbag reader: " + name() + ": byte " + std::to_string(slot.offset) +
                            ": a second " + (port ? "port" : "starboard") +
                            " image of the same header.stamp; the first skipped");
  }
  slot = std::move(side);
  if (pair.first.present && pair.second.present) complete(stamp_ns);
  while (pending_.size() > kMaxPending) {
    const auto oldest = pending_.begin();
    const Side& s = oldest->second.first.present ? oldest->second.first : oldest->second.second;
    report(s.offset, "rosbag reader: " + name() + ": byte " + std::to_string(s.offset) +
                         ": image without its other side (header.stamp " +
                         std::to_string(oldest->first) + " ns); skipped");
    pending_.erase(oldest);
  }
}

void Reader::complete(std::uint64_t stamp_ns) {
  auto node = pending_.extract(stamp_ns);
  Side& port = node.mapped().first;
  Side& stbd = node.mapped().second;
  Ping p;
  p.sonar.time_utc = utc_from_ns(stamp_ns);
  p.sonar.ping_number = port.seq;
  p.sonar.sound_speed_m_s = port.sound_speed_m_s;
  p.sonar.slant_range_m = port.slant_range_m;
  if (std::abs(stbd.slant_range_m / static_cast<double>(stbd.samples.size()) -
               port.slant_range_m / static_cast<double>(port.samples.size())) >
      1e-6 * port.slant_range_m / static_cast<double>(port.samples.size())) {
    report(stbd.offset, "rosbag reader: " + name() + ": byte " + std::to_string(stbd.offset) +
                            ": starboard sample spacing differs from port's; port's used");
  }
  p.sonar.port = std::move(port.samples);
  p.sonar.starboard = std::move(stbd.samples);
  p.offset = port.offset;
  p.index = port.ordinal;
  p.dtype = port.dtype;
  const std::uint64_t after = std::max(port.ordinal, stbd.ordinal);
  if (const Fix* f = at_or_before(fixes_, stamp_ns, after); f && f->valid) {
    p.sonar.sensor_position = f->position;
    p.nav_valid = true;
  }
  if (ImuSample* s = at_or_before(imu_, stamp_ns, after); s && s->known) {
    p.sonar.heading_true_rad = s->attitude.heading_true_rad;
    p.sonar.pitch_rad = s->attitude.pitch_rad;
    p.sonar.roll_rad = s->attitude.roll_rad;
    p.attitude_valid = true;
    s->used = true;
  }
  ready_.push_back(std::move(p));
}

void Reader::finish() {
  for (const auto& [stamp, pair] : pending_) {
    const Side& s = pair.first.present ? pair.first : pair.second;
    report(s.offset, "rosbag reader: " + name() + ": byte " + std::to_string(s.offset) +
                         ": image without its other side (header.stamp " + std::to_string(stamp) +
                         " ns); skipped");
  }
  pending_.clear();
  finished_ = true;
}

bool Reader::next_ping(Ping& ping) {
  while (ready_.empty()) {
    if (next_chunk_ < chunks_.size()) {
      scan_chunk(next_chunk_++, true);
    } else {
      if (!finished_) finish();
      return false;
    }
  }
  ping = std::move(ready_.front());
  ready_.pop_front();
  return true;
}

}  // namespace sonarsynth::rosbag
