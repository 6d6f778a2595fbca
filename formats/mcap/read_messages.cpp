// SPDX-License-Identifier: MIT
// MCAP reader, the messages (docs/robotics.md, "Reading bags"): the CDR of RawSonarImage,
// NavSatFix, Imu and TFMessage field by field: the writer's mapping reversed. The sides paired
// by header.stamp, the navigation and attitude at or before each ping: the ROS 1 bag reader's
// formats/rosbag/ping_assembler.cpp. The container: formats/mcap/reader.cpp.
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/mcap/read_records.hpp"
#include "sonarsynth/formats/mcap/reader.hpp"
#include "sonarsynth/formats/rosbag/ping_assembler.hpp"

namespace sonarsynth::mcap {

using rosbag::read_image_fields;
using rosbag::read_imu;
using rosbag::read_tilt;

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
    const auto status = static_cast<std::int8_t>(c.u8("status.status"));
    c.u16("status.service");
    const double lat = c.f64("latitude"), lon = c.f64("longitude");
    pings_->add_fix(stamp, ordinal_, status, lat, lon);
  } else if (kind == Kind::kImu) {
    pings_->add_imu(read_imu(c, stamp, ordinal_));
  } else {
    image(c, stamp, frame, info, images);
  }
}

void Reader::transforms(read::Cdr& c) {
  const auto header = [](read::Cdr& h) {
    std::string_view parent;
    h.header(parent);
  };
  read_tilt(c, header, tilt_rad_);
}

void Reader::image(read::Cdr& c, std::uint64_t stamp, std::string_view frame,
                   const ChannelInfo& info, bool images) {
  add_image(read_image_fields(c),
            {offset_, ordinal_, sequence_, stamp, frame, info.topic, info.schema}, images);
}

bool Reader::next_ping(Ping& ping) {
  return next_assembled_ping(ping, blocks_.size(),
                             [this](std::size_t block) { read_block(block, true); });
}

}  // namespace sonarsynth::mcap
