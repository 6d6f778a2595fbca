// SPDX-License-Identifier: MIT
// MCAP reader, the container (docs/robotics.md, "Reading bags"): the footer, the summary and its
// CRC, the chunk indexes or a walk of the records, chunks (zstd or uncompressed, CRC) and their
// message indexes. The messages: formats/mcap/read_messages.cpp.
#include "sonarsynth/formats/mcap/reader.hpp"

#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <map>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/mcap/opcodes.hpp"
#include "sonarsynth/formats/mcap/read_records.hpp"
#include "sonarsynth/formats/rosbag/ping_assembler.hpp"

namespace sonarsynth::mcap {
namespace {

constexpr std::uint64_t kFooterBytes = 1 + 8 + 20;  // opcode, length, content
constexpr std::uint64_t kMaxChunkBytes = std::uint64_t{1} << 30;

using read::Fields;
using read::Where;

/// A record at buf[at]: opcode and content, bounds-checked against the buffer.
struct RecordView {
  std::uint8_t op = 0;
  std::span<const std::uint8_t> content;
  std::size_t size = 0;  ///< 9 + content
};

RecordView record_at(std::span<const std::uint8_t> buf, std::size_t at, std::uint64_t base,
                     const Where& w) {
  const std::size_t left = buf.size() - at;
  if (left < 9) {
    read::fail(w, base + at,
               "record opcode and length: " + std::to_string(left) + " bytes left, 9 needed");
  }
  RecordView r;
  r.op = buf[at];
  const std::uint64_t n = read::le(buf.data() + at + 1, 8);
  if (n > left - 9) {
    read::fail(w, base + at + 1,
               "record (opcode " + std::to_string(r.op) + ") length = " + std::to_string(n) +
                   ": past the end (" + std::to_string(left - 9) + " bytes left)");
  }
  r.content = buf.subspan(at + 9, static_cast<std::size_t>(n));
  r.size = static_cast<std::size_t>(9 + n);
  return r;
}

std::uint32_t crc32_of(std::span<const std::uint8_t> b) {
  return static_cast<std::uint32_t>(crc32_z(0L, b.data(), b.size()));
}

}  // namespace

namespace read {

std::string position(const Where& w, std::uint64_t at) {
  return w.chunk == 0 ? "byte " + std::to_string(at)
                      : "chunk at byte " + std::to_string(w.chunk) + ", uncompressed byte " +
                            std::to_string(at);
}

void fail(const Where& w, std::uint64_t at, const std::string& what) {
  throw FormatError("mcap reader: " + w.file + ": " + position(w, at) + ": " + what);
}

}  // namespace read

Reader::Reader(const std::filesystem::path& path) : Reader(xtf::open_file_source(path)) {}

Reader::Reader(std::span<const std::uint8_t> bytes, std::string name)
    : Reader(xtf::memory_source(bytes, std::move(name))) {}

Reader::Reader(std::unique_ptr<xtf::ByteSource> source)
    : BagReaderBase(std::move(source), "mcap reader", true) {
  open();
}

void Reader::open() {
  const Where w{name()};
  size_ = source_->size();
  std::array<std::uint8_t, 8> magic{};
  if (size_ >= magic.size()) source_->read(0, magic);
  if (size_ < magic.size() || magic != kMagic) {
    read::fail(w, 0, "not an MCAP file (the file does not start with the MCAP magic 89 MCAP0)");
  }
  if (size_ < 2 * magic.size() + kFooterBytes) {
    read::fail(w, size_, "truncated: " + std::to_string(size_) + " bytes, no room for the footer");
  }
  std::array<std::uint8_t, kFooterBytes + 8> tail{};
  const std::uint64_t footer_pos = size_ - tail.size();
  source_->read(footer_pos, tail);
  if (!std::equal(kMagic.begin(), kMagic.end(), tail.begin() + kFooterBytes)) {
    read::fail(w, size_ - 8, "truncated or damaged: the file does not end with the MCAP magic");
  }
  if (tail[0] != kFooter || read::le(tail.data() + 1, 8) != 20) {
    read::fail(w, footer_pos,
               "footer: opcode " + std::to_string(tail[0]) + " and length " +
                   std::to_string(read::le(tail.data() + 1, 8)) +
                   ", expected 2 and 20 before the closing magic");
  }
  // The header record.
  {
    std::array<std::uint8_t, 9> head{};
    source_->read(8, head);
    const std::uint64_t n = read::le(head.data() + 1, 8);
    if (head[0] != kHeader) {
      read::fail(w, 8, "opcode " + std::to_string(head[0]) + ": expected the header record (1)");
    }
    if (n > std::min<std::uint64_t>(footer_pos - 17, 1 << 20)) {
      read::fail(w, 9, "header record length = " + std::to_string(n) + ": past the end or > 1 MiB");
    }
    buffer_.resize(static_cast<std::size_t>(n));
    source_->read(17, buffer_);
    Fields f(buffer_, 17, w, "header");
    profile_ = f.str("profile");
    library_ = f.str("library");
  }
  const std::uint64_t summary_start = read::le(tail.data() + 9, 8);
  const auto crc = static_cast<std::uint32_t>(read::le(tail.data() + 25, 4));
  if (summary_start != 0) read_summary(summary_start, footer_pos, crc);
  if (!indexed_) scan_records(summary_start != 0 ? summary_start : footer_pos);
  for (std::size_t k = 0; k < blocks_.size(); ++k) read_block(k, false);
  pings_->sort();
  if (image_info_ && tilt_rad_) image_info_->tilt_rad = *tilt_rad_;
}

void Reader::read_summary(std::uint64_t summary_start, std::uint64_t footer_pos,
                          std::uint32_t crc) {
  const Where w{name()};
  if (summary_start < 8 || summary_start > footer_pos) {
    read::fail(w, footer_pos + 9,
               "footer summary_start = " + std::to_string(summary_start) +
                   ": outside the file's records (8.." + std::to_string(footer_pos) + ")");
  }
  // The summary, the summary offsets and the footer up to its CRC field.
  std::vector<std::uint8_t> summary(static_cast<std::size_t>(size_ - 12 - summary_start));
  source_->read(summary_start, summary);
  if (crc != 0 && crc32_of(summary) != crc) {
    read::fail(w, footer_pos + 25,
               "footer summary_crc = " + std::to_string(crc) + ": the summary's CRC-32 is " +
                   std::to_string(crc32_of(summary)));
  }
  const std::span<const std::uint8_t> records(summary.data(),
                                              static_cast<std::size_t>(footer_pos - summary_start));
  std::vector<Block> chunks;
  std::map<std::uint16_t, std::uint64_t> counts;
  bool statistics = false;
  for (std::size_t at = 0; at < records.size();) {
    const RecordView r = record_at(records, at, summary_start, w);
    const std::uint64_t content_pos = summary_start + at + 9;
    Fields f(r.content, content_pos, w, r.op == kStatistics ? "statistics" : "chunk index");
    if (r.op == kSchema) {
      add_schema(r.content, content_pos);
    } else if (r.op == kChannel) {
      add_channel(r.content, content_pos);
    } else if (r.op == kStatistics) {
      f.take(8 + 2 + 4 * 3, "counts");
      chunk_count_ = f.u32("chunk_count");
      f.take(16, "message_start_time, message_end_time");
      const std::uint64_t counts_at = f.offset() + 4;
      Fields c(f.bytes("channel_message_counts"), counts_at, w, "statistics");
      while (c.left() > 0) {
        const std::uint16_t id = c.u16("channel_message_counts.channel_id");
        counts[id] = c.u64("channel_message_counts.count");
      }
      statistics = true;
    } else if (r.op == kChunkIndex) {
      f.take(16, "message_start_time, message_end_time");
      Block b;
      b.chunk = true;
      b.offset = f.u64("chunk_start_offset");
      b.chunk_length = f.u64("chunk_length");
      f.bytes("message_index_offsets");
      const std::uint64_t index_length = f.u64("message_index_length");
      if (b.offset < 8 || b.offset > summary_start || b.chunk_length > summary_start - b.offset ||
          index_length > summary_start - b.offset - b.chunk_length) {
        read::fail(w, content_pos + 16,
                   "chunk index chunk_start_offset = " + std::to_string(b.offset) +
                       ", chunk_length = " + std::to_string(b.chunk_length) +
                       ", message_index_length = " + std::to_string(index_length) +
                       ": past the data section (which ends at byte " +
                       std::to_string(summary_start) + ")");
      }
      b.length = b.chunk_length + index_length;
      chunks.push_back(b);
    }
    at += r.size;
  }
  if (statistics) {
    for (ChannelInfo& c : channels_) c.messages = counts[c.id];
    count_messages_ = false;
  }
  // Without chunk indexes (an unchunked file) the records are walked.
  indexed_ = !chunks.empty();
  if (!indexed_) return;
  std::sort(chunks.begin(), chunks.end(),
            [](const Block& a, const Block& b) { return a.offset < b.offset; });
  blocks_ = std::move(chunks);
  chunk_count_ = blocks_.size();
}

void Reader::add_schema(std::span<const std::uint8_t> content, std::uint64_t pos) {
  const Where w{name()};
  Fields f(content, pos, w, "schema");
  const std::uint16_t id = f.u16("id");
  const std::string_view schema = f.str("name");
  const std::string_view encoding = f.str("encoding");
  if (id == 0) f.fail_at("schema id = 0: reserved for 'no schema'");
  schemas_.try_emplace(
      id, encoding == "ros2msg" || encoding == "ros2idl" ? std::string(schema) : std::string());
}

void Reader::add_channel(std::span<const std::uint8_t> content, std::uint64_t pos) {
  const Where w{name()};
  Fields f(content, pos, w, "channel");
  ChannelInfo c;
  c.id = f.u16("id");
  const std::uint16_t schema_id = f.u16("schema_id");
  c.topic = f.str("topic");
  c.message_encoding = f.str("message_encoding");
  f.bytes("metadata");
  if (by_id_.contains(c.id)) return;
  if (schema_id != 0) {
    const auto s = schemas_.find(schema_id);
    if (s == schemas_.end()) {
      f.fail_at("channel " + std::to_string(c.id) + " (" + c.topic + ") schema_id = " +
                std::to_string(schema_id) + ": no schema record with that id before it");
    }
    c.schema = s->second;
  }
  // rosbag2 writes "pkg/msg/Type"; "pkg/Type" is accepted too.
  std::string type = c.schema;
  if (const auto k = type.find("/msg/"); k != std::string::npos) type.erase(k, 4);
  Kind kind = Kind::kNone;
  if (type == "marine_acoustic_msgs/RawSonarImage") kind = Kind::kImage;
  if (type == "sensor_msgs/NavSatFix") kind = Kind::kFix;
  if (type == "sensor_msgs/Imu") kind = Kind::kImu;
  if (type == "tf2_msgs/TFMessage") kind = Kind::kTf;
  if (kind != Kind::kNone && c.message_encoding != "cdr") {
    report(pos, "mcap reader: " + name() + ": byte " + std::to_string(pos) + ": channel " +
                    std::to_string(c.id) + " (" + c.topic + ") message_encoding = '" +
                    c.message_encoding + "': only cdr is read; not read");
    kind = Kind::kNone;
  }
  c.decoded = kind != Kind::kNone;
  by_id_[c.id] = channels_.size();
  channels_.push_back(std::move(c));
  kinds_.push_back(kind);
}

void Reader::scan_records(std::uint64_t end) {
  const Where w{name()};
  std::array<std::uint8_t, 9> head{};
  for (std::uint64_t at = 8; at < end;) {
    if (end - at < head.size()) {
      read::fail(w, at,
                 "record opcode and length: " + std::to_string(end - at) +
                     " bytes left before the footer, 9 needed");
    }
    source_->read(at, head);
    const std::uint64_t n = read::le(head.data() + 1, 8);
    if (n > end - at - 9) {
      read::fail(w, at + 1,
                 "record (opcode " + std::to_string(head[0]) + ") length = " + std::to_string(n) +
                     ": past the end (" + std::to_string(end - at - 9) + " bytes left)");
    }
    if (head[0] == kDataEnd) break;
    if (head[0] == kSchema || head[0] == kChannel) {
      buffer_.resize(static_cast<std::size_t>(n));
      source_->read(at + 9, buffer_);
      if (head[0] == kSchema) add_schema(buffer_, at + 9);
      if (head[0] == kChannel) add_channel(buffer_, at + 9);
    } else if (head[0] == kChunk || head[0] == kMessage) {
      blocks_.push_back({at, 9 + n, 9 + n, head[0] == kChunk});
      chunk_count_ += head[0] == kChunk ? 1u : 0u;
    }
    at += 9 + n;
  }
}

std::span<const std::uint8_t> Reader::decompress(std::span<const std::uint8_t> chunk,
                                                 std::uint64_t pos, bool check_crc) {
  const Where w{name()};
  Fields f(chunk, pos + 9, w, "chunk");
  f.take(16, "message_start_time, message_end_time");
  const std::uint64_t size = f.u64("uncompressed_size");
  const std::uint32_t crc = f.u32("uncompressed_crc");
  const std::string_view compression = f.str("compression");
  const std::uint64_t n = f.u64("records");
  const std::uint64_t records_at = f.offset();
  const auto data =
      f.take(static_cast<std::size_t>(std::min<std::uint64_t>(n, f.left())), "records");
  if (data.size() != n) {
    read::fail(w, records_at - 8,
               "chunk records length = " + std::to_string(n) + ": past the end of the chunk (" +
                   std::to_string(data.size()) + " bytes left)");
  }
  std::span<const std::uint8_t> out = data;
  if (compression == "zstd") {
    if (size > kMaxChunkBytes) {
      read::fail(w, pos + 25,
                 "chunk uncompressed_size = " + std::to_string(size) +
                     ". Violated constraint: <= 2^30 bytes");
    }
    const unsigned long long frame = ZSTD_getFrameContentSize(data.data(), data.size());
    if (frame != ZSTD_CONTENTSIZE_UNKNOWN && frame != size) {
      read::fail(w, records_at,
                 "chunk zstd frame content size = " + std::to_string(frame) +
                     ", uncompressed_size = " + std::to_string(size));
    }
    chunk_.resize(static_cast<std::size_t>(size));
    const std::size_t got = ZSTD_decompress(chunk_.data(), chunk_.size(), data.data(), data.size());
    if (ZSTD_isError(got) || got != size) {
      read::fail(
          w, records_at,
          std::string("chunk records: zstd: ") +
              (ZSTD_isError(got)
                   ? ZSTD_getErrorName(got)
                   : std::to_string(got) + " bytes, uncompressed_size = " + std::to_string(size)));
    }
    out = chunk_;
  } else if (!compression.empty()) {
    read::fail(w, records_at - 12 - compression.size(),
               "chunk compression = '" + std::string(compression) +
                   "': not read (zstd or uncompressed chunks only)");
  } else if (size != n) {
    read::fail(w, pos + 25,
               "chunk uncompressed_size = " + std::to_string(size) +
                   ", records length = " + std::to_string(n) + ": must be equal uncompressed");
  }
  // The constructor's pass checks every chunk; the pings' pass reads them again.
  if (check_crc && crc != 0 && crc32_of(out) != crc) {
    read::fail(w, pos + 33,
               "chunk uncompressed_crc = " + std::to_string(crc) + ": the records' CRC-32 is " +
                   std::to_string(crc32_of(out)));
  }
  return out;
}

void Reader::read_block(std::size_t block, bool images) {
  const Where w{name()};
  const Block& b = blocks_[block];
  buffer_.resize(static_cast<std::size_t>(b.length));
  source_->read(b.offset, buffer_);
  const RecordView r = record_at(buffer_, 0, b.offset, w);
  if (!b.chunk) {
    message(buffer_, 0, b.offset, std::uint64_t{block} << 32, images);
    return;
  }
  if (r.op != kChunk || r.size != b.chunk_length) {
    read::fail(w, b.offset,
               "opcode " + std::to_string(r.op) + ", " + std::to_string(r.size) +
                   " bytes: the chunk index does not point at a chunk record of its chunk_length " +
                   std::to_string(b.chunk_length));
  }
  const std::span<const std::uint8_t> records = decompress(r.content, b.offset, !images);
  if (indexed_) {
    chunk_messages(records, std::span<const std::uint8_t>(buffer_).subspan(r.size), block, images);
    return;
  }
  const Where in_chunk{name(), b.offset};
  for (std::size_t at = 0; at < records.size();) {
    const RecordView m = record_at(records, at, 0, in_chunk);
    if (m.op == kSchema && !images) add_schema(m.content, at + 9);
    if (m.op == kChannel && !images) add_channel(m.content, at + 9);
    if (m.op == kMessage) {
      message(records.subspan(at, m.size), b.offset, at, (std::uint64_t{block} << 32) | at, images);
    }
    at += m.size;
  }
}

void Reader::chunk_messages(std::span<const std::uint8_t> records,
                            std::span<const std::uint8_t> indexes, std::size_t block, bool images) {
  // The message indexes of the channels this pass decodes, merged in file order.
  const std::uint64_t pos = blocks_[block].offset + blocks_[block].chunk_length;
  const Where w{name()};
  entries_.clear();
  for (std::size_t at = 0; at < indexes.size();) {
    const RecordView r = record_at(indexes, at, pos, w);
    if (r.op != kMessageIndex) {
      read::fail(w, pos + at,
                 "opcode " + std::to_string(r.op) + ": expected a message index record (7) after " +
                     "the chunk");
    }
    Fields f(r.content, pos + at + 9, w, "message index");
    const std::uint16_t channel = f.u16("channel_id");
    const auto it = by_id_.find(channel);
    const Kind kind = it == by_id_.end() ? Kind::kNone : kinds_[it->second];
    const std::uint64_t entries_at = f.offset() + 4;
    const auto bytes = f.bytes("records");
    if (count_messages_ && !images && it != by_id_.end()) {
      channels_[it->second].messages += bytes.size() / 16;
    }
    if (kind != Kind::kNone &&
        (images ? kind == Kind::kImage : kind != Kind::kImage || !image_info_)) {
      Fields e(bytes, entries_at, w, "message index");
      while (e.left() > 0) {
        e.u64("records.log_time");
        const std::uint64_t offset = e.u64("records.offset");
        if (offset >= records.size()) {
          e.fail_at("message index records.offset = " + std::to_string(offset) +
                    ": past the chunk's " + std::to_string(records.size()) + " bytes of records");
        }
        entries_.emplace_back(offset, channel);
      }
    }
    at += r.size;
  }
  std::sort(entries_.begin(), entries_.end());
  const Where in_chunk{name(), blocks_[block].offset};
  for (const auto& [offset, channel] : entries_) {
    const auto at = static_cast<std::size_t>(offset);
    const RecordView m = record_at(records, at, 0, in_chunk);
    if (m.op != kMessage || m.content.size() < 2 || read::le(m.content.data(), 2) != channel) {
      read::fail(in_chunk, at,
                 "message index of channel " + std::to_string(channel) +
                     ": offset does not point at a message record of that channel");
    }
    message(records.subspan(at, m.size), blocks_[block].offset, at,
            (std::uint64_t{block} << 32) | at, images);
  }
}

}  // namespace sonarsynth::mcap
