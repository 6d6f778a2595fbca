// SPDX-License-Identifier: MIT
// ROS 1 bag reader, format 2.0 (docs/rosbag.md, "Reading bags"): the index, uncompressed
// chunks, and the writer's message mapping reversed.
#include "sonarsynth/formats/rosbag/reader.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <string_view>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/rosbag/bag_records.hpp"
#include "sonarsynth/formats/rosbag/messages.hpp"
#include "sonarsynth/formats/rosbag/ping_assembler.hpp"

namespace sonarsynth::rosbag {
namespace {

using records::Cursor;
using records::fail;
using records::field;
using records::field_str;
using records::field_uint;
using records::Fields;
using records::le;
using records::parse_fields;
using records::parse_record;
using records::Record;

}  // namespace

Reader::Reader(const std::filesystem::path& path) : Reader(xtf::open_file_source(path)) {}

Reader::Reader(std::span<const std::uint8_t> bytes, std::string name)
    : Reader(xtf::memory_source(bytes, std::move(name))) {}

BagReaderBase::BagReaderBase(std::unique_ptr<xtf::ByteSource> source, std::string_view reader,
                             bool nav_before_images)
    : source_(std::move(source)),
      pings_(std::make_unique<PingAssembler>(std::string(reader) + ": " + source_->name() + ": ",
                                             nav_before_images
                                                 ? PingAssembler::NavOrder::kBeforeImages
                                                 : PingAssembler::NavOrder::kAfterImages,
                                             [this](std::uint64_t offset, std::string message) {
                                               report(offset, std::move(message));
                                             })) {}

BagReaderBase::~BagReaderBase() = default;

const std::string& BagReaderBase::name() const {
  return source_->name();
}

const std::vector<ImuSample>& BagReaderBase::imu() const {
  return pings_->imu();
}

void BagReaderBase::report(std::uint64_t offset, std::string message) {
  ++anomaly_count_;
  if (anomalies_.size() < 1000) anomalies_.push_back({offset, std::move(message)});
}

void BagReaderBase::add_image(const ImageFields& f, const ImageSource& source, bool images) {
  if (!image_info_) image_info_ = f.info;
  if (images) pings_->add_image(f, source);
}

bool BagReaderBase::next_assembled_ping(Ping& ping, std::size_t blocks,
                                        const std::function<void(std::size_t)>& read_images) {
  while (!pings_->pop(ping)) {
    if (next_block_ >= blocks) {
      pings_->finish();
      return false;
    }
    read_images(next_block_++);
  }
  return true;
}

Reader::Reader(std::unique_ptr<xtf::ByteSource> source)
    : BagReaderBase(std::move(source), "rosbag reader", false) {
  open();
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
  pings_->sort();
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
      const auto status = static_cast<std::int8_t>(c.u8("status.status"));
      c.take(2, "status.service");
      const double lat = c.f64("latitude"), lon = c.f64("longitude");
      pings_->add_fix(stamp, ordinal_, status, lat, lon);
    } else if (kind == Kind::kImu) {
      pings_->add_imu(read_imu(c, stamp, ordinal_));
    } else {
      image(c, seq, stamp, frame, info, offset, images);
    }
  } catch (const FormatError& e) {
    report(offset, e.what());
  }
}

void Reader::transforms(records::Cursor& c) {
  const auto header = [](records::Cursor& h) {
    std::uint32_t seq = 0;
    std::string_view parent;
    h.header(seq, parent);
  };
  read_tilt(c, header, tilt_rad_);
}

void Reader::image(Cursor& c, std::uint32_t seq, std::uint64_t stamp, std::string_view frame,
                   const ConnectionInfo& info, std::uint64_t offset, bool images) {
  add_image(read_image_fields(c), {offset, ordinal_, seq, stamp, frame, info.topic, info.type},
            images);
}

bool Reader::next_ping(Ping& ping) {
  return next_assembled_ping(ping, chunks_.size(),
                             [this](std::size_t chunk) { scan_chunk(chunk, true); });
}

}  // namespace sonarsynth::rosbag
