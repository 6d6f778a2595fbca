// SPDX-License-Identifier: MIT
// MCAP reader, the messages (docs/robotics.md, "Reading bags"): the CDR of RawSonarImage,
// NavSatFix, Imu and TFMessage field by field, the sides paired by header.stamp, the navigation
// and attitude at or before each ping: the writer's mapping reversed. The container:
// formats/mcap/reader.cpp.
#include <algorithm>
#include <cctype>
#include <cmath>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/mcap/read_records.hpp"
#include "sonarsynth/formats/mcap/reader.hpp"
#include "sonarsynth/formats/rosbag/bag_records.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::mcap {
namespace {

constexpr std::size_t kMaxPending = 4096;  // unpaired image stamps kept before giving up on one

using rosbag::records::attitude_from_quaternion;
using rosbag::records::decode_samples;
using rosbag::records::kDtypeBytes;

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

/// +1 port, -1 starboard, 0 neither: from the frame id, else from the topic (docs/robotics.md).
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
/// with that stamp the last written before `ordinal` (the writer puts a ping's navigation before
/// its images), else the first.
template <class T>
T* at_or_before(std::vector<T>& v, std::uint64_t stamp, std::uint64_t ordinal) {
  auto it = std::upper_bound(v.begin(), v.end(), stamp,
                             [](std::uint64_t s, const T& e) { return s < e.stamp_ns; });
  if (it == v.begin()) return nullptr;
  const std::uint64_t s = std::prev(it)->stamp_ns;
  auto first = std::lower_bound(v.begin(), it, s,
                                [](const T& e, std::uint64_t t) { return e.stamp_ns < t; });
  for (auto k = it; k != first; --k) {
    if (std::prev(k)->ordinal < ordinal) return &*std::prev(k);
  }
  return &*first;
}

}  // namespace

void Reader::message(std::span<const std::uint8_t> record, std::uint64_t chunk_pos,
                     std::uint64_t at, std::uint64_t ordinal, bool images) {
  const read::Where w{name(), chunk_pos};
  read::Fields f(record.subspan(9), at + 9, w, "message");
  const std::uint16_t channel = f.u16("channel_id");
  sequence_ = f.u32("sequence");
  f.take(8 + 8, "log_time, publish_time");
  const std::uint64_t data_at = f.offset();
  const auto data = f.take(f.left(), "data");
  // Anomalies carry the file offset of the chunk (or of the message outside chunks).
  offset_ = chunk_pos != 0 ? chunk_pos : at;
  ordinal_ = ordinal;
  const auto it = by_id_.find(channel);
  if (it == by_id_.end()) {
    if (!images) {
      report(offset_, "mcap reader: " + name() + ": " + read::position(w, at) +
                          ": message of channel " + std::to_string(channel) +
                          ", which no channel record defines; skipped");
    }
    return;
  }
  if (!images && count_messages_) ++channels_[it->second].messages;
  const Kind kind = kinds_[it->second];
  // The constructor's pass reads navigation, attitude and the first image's settings; the
  // pings' pass reads the images.
  if (kind == Kind::kNone) return;
  if (images ? kind != Kind::kImage : kind == Kind::kImage && image_info_) return;
  const ChannelInfo& info = channels_[it->second];
  try {
    read::Cdr c(data, data_at, w, info.schema);
    decode(kind, info, c, images);
  } catch (const FormatError& e) {
    report(offset_, e.what());
  }
}

void Reader::decode(Kind kind, const ChannelInfo& info, read::Cdr& c, bool images) {
  if (kind == Kind::kTf) return transforms(c);
  std::string_view frame;
  const std::uint64_t stamp = c.header(frame);
  if (kind == Kind::kFix) {
    Fix f{stamp, ordinal_, {}, false};
    const auto status = static_cast<std::int8_t>(c.u8("status.status"));
    c.u16("status.service");
    const double lat = c.f64("latitude"), lon = c.f64("longitude");
    f.valid = status >= 0 && std::abs(lat) <= 90.0 && std::abs(lon) <= 180.0 &&
              (lat != 0.0 || lon != 0.0);
    if (f.valid) f.position = {rad_from_deg(lat), rad_from_deg(lon), 0.0};
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
    image(c, stamp, frame, info, images);
  }
}

void Reader::transforms(read::Cdr& c) {
  // The writer's port transform: yaw +pi/2, then pitch = tilt about the new y (docs/robotics.md,
  // "/tf_static"); the pitch of its ZYX angles is the tilt.
  const std::uint32_t n = c.u32("transforms");
  for (std::uint32_t k = 0; k < n && !tilt_rad_; ++k) {
    std::string_view parent;
    c.header(parent);
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

void Reader::image(read::Cdr& c, std::uint64_t stamp, std::string_view frame,
                   const ChannelInfo& info, bool images) {
  Side side;
  side.offset = offset_;
  side.ordinal = ordinal_;
  side.sequence = sequence_;
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
  const std::string where = "mcap reader: " + name() + ": byte " + std::to_string(offset_) + ": ";
  const auto bad = [&](const std::string& what) {
    report(offset_, where + info.schema + " (" + info.topic + ") " + what + "; skipped");
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
    report(offset_, where + "ping_info.sound_speed = " + std::to_string(side.sound_speed_m_s) +
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
    report(slot.offset, "mcap reader: " + name() + ": byte " + std::to_string(slot.offset) +
                            ": a second " + (port ? "port" : "starboard") +
                            " image of the same header.stamp; the first skipped");
  }
  slot = std::move(side);
  if (pair.first.present && pair.second.present) complete(stamp_ns);
  while (pending_.size() > kMaxPending) {
    const auto oldest = pending_.begin();
    const Side& s = oldest->second.first.present ? oldest->second.first : oldest->second.second;
    report(s.offset, "mcap reader: " + name() + ": byte " + std::to_string(s.offset) +
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
  p.sonar.ping_number = port.sequence;
  p.sonar.sound_speed_m_s = port.sound_speed_m_s;
  p.sonar.slant_range_m = port.slant_range_m;
  const double port_step = port.slant_range_m / static_cast<double>(port.samples.size());
  const double stbd_step = stbd.slant_range_m / static_cast<double>(stbd.samples.size());
  if (std::abs(stbd_step - port_step) > 1e-6 * port_step) {
    report(stbd.offset, "mcap reader: " + name() + ": byte " + std::to_string(stbd.offset) +
                            ": starboard sample spacing differs from port's; port's used");
  }
  p.sonar.port = std::move(port.samples);
  p.sonar.starboard = std::move(stbd.samples);
  p.offset = port.offset;
  p.index = port.ordinal;
  p.dtype = port.dtype;
  const std::uint64_t before = std::min(port.ordinal, stbd.ordinal);
  if (const Fix* f = at_or_before(fixes_, stamp_ns, before); f && f->valid) {
    p.sonar.sensor_position = f->position;
    p.nav_valid = true;
  }
  if (ImuSample* s = at_or_before(imu_, stamp_ns, before); s && s->known) {
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
    report(s.offset, "mcap reader: " + name() + ": byte " + std::to_string(s.offset) +
                         ": image without its other side (header.stamp " + std::to_string(stamp) +
                         " ns); skipped");
  }
  pending_.clear();
  finished_ = true;
}

bool Reader::next_ping(Ping& ping) {
  while (ready_.empty()) {
    if (next_block_ < blocks_.size()) {
      read_block(next_block_++, true);
    } else {
      if (!finished_) finish();
      return false;
    }
  }
  ping = std::move(ready_.front());
  ready_.pop_front();
  return true;
}

}  // namespace sonarsynth::mcap
