// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/xtf/reader.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <sstream>
#include <type_traits>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/time_fields.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::xtf {
namespace {

constexpr double kMetresPerSecondPerKnot = 1852.0 / 3600.0;

std::string hex(std::uint64_t v) {
  std::ostringstream os;
  os << "0x" << std::hex << std::uppercase << v;
  return os.str();
}

std::string at(std::uint64_t offset, const std::string& name) {
  return " at byte " + std::to_string(offset) + " of " + name;
}

/// IBM System/360 single-precision float (sign, base-16 exponent biased by 64, 24-bit fraction).
float ibm_to_float(std::uint32_t v) {
  const std::uint32_t fraction = v & 0x00FFFFFFu;
  if (fraction == 0) return 0.0f;
  const int exponent = static_cast<int>((v >> 24) & 0x7Fu) - 64;
  const double magnitude = std::ldexp(static_cast<double>(fraction), 4 * exponent - 24);
  return static_cast<float>((v & 0x80000000u) ? -magnitude : magnitude);
}

enum class SampleKind { kU8, kI8, kU16, kI16, kU32, kI32, kF32, kIbm32, kUnsupported };

SampleKind sample_kind(const XtfChanInfo& c, Signedness signedness, std::uint16_t& bytes) {
  const bool is_signed = signedness == Signedness::kSigned ||
                         (signedness == Signedness::kFromUniPolar && c.UniPolar == 0);
  switch (c.SampleFormat) {
    case 1:
      bytes = 4;
      return SampleKind::kIbm32;
    case 2:
      bytes = 4;
      return is_signed ? SampleKind::kI32 : SampleKind::kU32;
    case 3:
      bytes = 2;
      return is_signed ? SampleKind::kI16 : SampleKind::kU16;
    case 5:
      bytes = 4;
      return SampleKind::kF32;
    case 8:
      bytes = 1;
      return is_signed ? SampleKind::kI8 : SampleKind::kU8;
    case 0:
      break;
    default:
      bytes = 0;
      return SampleKind::kUnsupported;
  }
  bytes = c.BytesPerSample;
  switch (c.BytesPerSample) {
    case 1:
      return is_signed ? SampleKind::kI8 : SampleKind::kU8;
    case 2:
      return is_signed ? SampleKind::kI16 : SampleKind::kU16;
    case 4:
      return is_signed ? SampleKind::kI32 : SampleKind::kU32;
    default:
      break;
  }
  return SampleKind::kUnsupported;
}

void convert_samples(const std::uint8_t* p, std::size_t n, SampleKind kind, float* out) {
  const auto le16 = [](const std::uint8_t* b) {
    return static_cast<std::uint16_t>(b[0] | (b[1] << 8));
  };
  const auto le32 = [](const std::uint8_t* b) {
    return static_cast<std::uint32_t>(b[0]) | (static_cast<std::uint32_t>(b[1]) << 8) |
           (static_cast<std::uint32_t>(b[2]) << 16) | (static_cast<std::uint32_t>(b[3]) << 24);
  };
  switch (kind) {
    case SampleKind::kU8:
      for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(p[i]);
      break;
    case SampleKind::kI8:
      for (std::size_t i = 0; i < n; ++i)
        out[i] = static_cast<float>(static_cast<std::int8_t>(p[i]));
      break;
    case SampleKind::kU16:
      for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(le16(p + 2 * i));
      break;
    case SampleKind::kI16:
      for (std::size_t i = 0; i < n; ++i) {
        out[i] = static_cast<float>(static_cast<std::int16_t>(le16(p + 2 * i)));
      }
      break;
    case SampleKind::kU32:
      for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(le32(p + 4 * i));
      break;
    case SampleKind::kI32:
      for (std::size_t i = 0; i < n; ++i) {
        out[i] = static_cast<float>(static_cast<std::int32_t>(le32(p + 4 * i)));
      }
      break;
    case SampleKind::kF32:
      for (std::size_t i = 0; i < n; ++i) out[i] = std::bit_cast<float>(le32(p + 4 * i));
      break;
    case SampleKind::kIbm32:
      for (std::size_t i = 0; i < n; ++i) out[i] = ibm_to_float(le32(p + 4 * i));
      break;
    case SampleKind::kUnsupported:
      break;
  }
}

}  // namespace

const char* anomaly_kind_name(AnomalyKind kind) {
  switch (kind) {
    case AnomalyKind::kGarbageSkipped:
      return "garbage_skipped";
    case AnomalyKind::kBadRecordSize:
      return "bad_record_size";
    case AnomalyKind::kTruncatedPacket:
      return "truncated_packet";
    case AnomalyKind::kBadChannel:
      return "bad_channel";
    case AnomalyKind::kSamplesBeyondRecord:
      return "samples_beyond_record";
    case AnomalyKind::kOversizedPacket:
      return "oversized_packet";
    case AnomalyKind::kHeaderChannelCount:
      return "header_channel_count";
    case AnomalyKind::kInvalidTime:
      return "invalid_time";
    case AnomalyKind::kTimeBackwards:
      return "time_backwards";
    case AnomalyKind::kZeroNavigation:
      return "zero_navigation";
  }
  return "unknown";
}

AttitudeSample attitude_sample(const XtfAttitudeData& d) {
  AttitudeSample a;
  a.time_utc = UtcTime{std::chrono::seconds{d.SourceEpoch}} +
               std::chrono::microseconds{std::min<std::uint32_t>(d.EpochMicroseconds, 999999)};
  a.heading_true_rad = rad_from_deg(d.Heading);
  a.pitch_rad = rad_from_deg(d.Pitch);
  a.roll_rad = rad_from_deg(d.Roll);
  a.heave_m = d.Heave;
  a.yaw_rad = rad_from_deg(d.Yaw);
  return a;
}

void ReaderOptions::validate() const {
  if (max_packet_bytes < 64) {
    throw InputError("xtf reader: max_packet_bytes = " + std::to_string(max_packet_bytes) +
                     ". Violated constraint: max_packet_bytes >= 64");
  }
}

// ---------------------------------------------------------------------------------------------
Reader::Reader(const std::filesystem::path& path, ReaderOptions options)
    : Reader(open_file_source(path), options) {}

Reader::Reader(std::span<const std::uint8_t> bytes, std::string name, ReaderOptions options)
    : Reader(memory_source(bytes, std::move(name)), options) {}

Reader::Reader(std::unique_ptr<ByteSource> source, ReaderOptions options)
    : source_(std::move(source)), options_(options) {
  options_.validate();
  open();
}

Reader::~Reader() = default;

const std::string& Reader::name() const {
  return source_->name();
}

std::uint64_t Reader::total_anomalies() const {
  std::uint64_t n = 0;
  for (auto c : anomaly_counts_) n += c;
  return n;
}

void Reader::report(AnomalyKind kind, std::uint64_t offset, std::string message) {
  ++anomaly_counts_[static_cast<std::size_t>(kind)];
  if (anomalies_.size() < options_.max_anomaly_messages) {
    anomalies_.push_back({kind, offset, std::move(message), current_packet_});
  }
}

void Reader::open() {
  size_ = source_->size();
  const std::string& nm = source_->name();
  if (size_ < XtfFileHeader::kSize) {
    throw FormatError("xtf reader: " + nm + " has " + std::to_string(size_) +
                      " bytes, fewer than the 1024-byte XTF file header");
  }
  buffer_.resize(XtfFileHeader::kSize);
  source_->read(0, buffer_);
  ByteReader r(buffer_);
  header_ = XtfFileHeader::decode(r);
  if (header_.FileFormat != kFileFormat) {
    throw FormatError("xtf reader: FileFormat = " + hex(header_.FileFormat) + " at byte 0 of " +
                      nm + " (expected 0x7B): not an XTF file");
  }
  const std::uint32_t total = header_.total_channels();
  std::uint64_t blocks = XtfFileHeader::extra_blocks(total);
  // The header's counts are only trusted if the extra blocks exist and a packet follows them.
  data_offset_ = XtfFileHeader::kSize;
  chan_info_.assign(header_.ChanInfo.begin(), header_.ChanInfo.end());
  if (blocks > 0) {
    const std::uint64_t end = XtfFileHeader::kSize + blocks * 1024;
    const bool fits = end <= size_;
    const bool packet_follows = fits && (end == size_ || plausible_packet_at(end));
    if (packet_follows) {
      std::vector<std::uint8_t> block(1024);
      for (std::uint64_t b = 0; b < blocks; ++b) {
        source_->read(XtfFileHeader::kSize + b * 1024, block);
        ByteReader br(block);
        for (std::size_t i = 0; i < kChanInfoPerExtraBlock; ++i) {
          chan_info_.push_back(XtfChanInfo::decode(br));
        }
      }
      data_offset_ = end;
    } else {
      report(AnomalyKind::kHeaderChannelCount, 0,
             "xtf reader: the file header of " + nm + " declares " + std::to_string(total) +
                 " channels (" + std::to_string(blocks) +
                 " extra CHANINFO blocks) but no packet follows them; using the first 6 CHANINFO");
    }
  }
  if (total > 0 && total < chan_info_.size()) chan_info_.resize(total);
  pos_ = data_offset_;
}

bool Reader::plausible_packet_at(std::uint64_t offset) {
  if (offset > size_ || size_ - offset < XtfPacketHeader::kSize) return false;
  std::array<std::uint8_t, XtfPacketHeader::kSize> b{};
  source_->read(offset, b);
  ByteReader r(b);
  const XtfPacketHeader h = XtfPacketHeader::decode(r);
  return h.MagicNumber == kMagicNumber && h.NumBytesThisRecord >= XtfPacketHeader::kSize &&
         h.NumBytesThisRecord <= size_ - offset;
}

std::uint64_t Reader::find_next_packet(std::uint64_t from) {
  constexpr std::size_t kChunk = 64 * 1024;
  scan_buffer_.resize(kChunk);
  std::uint64_t start = from;
  while (start + 1 < size_) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(kChunk, size_ - start));
    source_->read(start, std::span<std::uint8_t>(scan_buffer_.data(), n));
    for (std::size_t i = 0; i + 1 < n; ++i) {
      if (scan_buffer_[i] == 0xCE && scan_buffer_[i + 1] == 0xFA &&
          plausible_packet_at(start + i)) {
        return start + i;
      }
    }
    if (n < 2) break;
    start += n - 1;  // overlap one byte so a CE FA pair across chunks is found
  }
  return size_;
}

bool Reader::next(Packet& packet) {
  const std::string& nm = source_->name();
  while (pos_ < size_) {
    current_packet_ = packets_;
    const std::uint64_t remaining = size_ - pos_;
    if (remaining < XtfPacketHeader::kSize) {
      report(AnomalyKind::kTruncatedPacket, pos_,
             "xtf reader: " + std::to_string(remaining) + " trailing bytes" + at(pos_, nm) +
                 " are too few for a packet header; ignored");
      pos_ = size_;
      return false;
    }
    std::array<std::uint8_t, XtfPacketHeader::kSize> hb{};
    source_->read(pos_, hb);
    ByteReader hr(hb);
    const XtfPacketHeader h = XtfPacketHeader::decode(hr);
    if (h.MagicNumber != kMagicNumber) {
      const std::uint64_t next_pos = find_next_packet(pos_ + 1);
      report(AnomalyKind::kGarbageSkipped, pos_,
             "xtf reader: MagicNumber = " + hex(h.MagicNumber) + at(pos_, nm) +
                 " (expected 0xFACE); skipped " + std::to_string(next_pos - pos_) +
                 " bytes to the next packet");
      pos_ = next_pos;
      continue;
    }
    const std::uint64_t n = h.NumBytesThisRecord;
    if (n < XtfPacketHeader::kSize || n > remaining) {
      const std::uint64_t next_pos = find_next_packet(pos_ + 2);
      if (n > remaining && next_pos == size_) {
        report(AnomalyKind::kTruncatedPacket, pos_,
               "xtf reader: last packet (HeaderType " + std::to_string(h.HeaderType) + ")" +
                   at(pos_, nm) + " is truncated: NumBytesThisRecord = " + std::to_string(n) +
                   " but only " + std::to_string(remaining) + " bytes remain; ignored");
      } else {
        report(AnomalyKind::kBadRecordSize, pos_,
               "xtf reader: NumBytesThisRecord = " + std::to_string(n) + at(pos_, nm) +
                   (n < XtfPacketHeader::kSize ? " (smaller than the 14-byte packet header)"
                                               : " runs past the end of the file") +
                   "; skipped " + std::to_string(next_pos - pos_) + " bytes to the next packet");
      }
      pos_ = next_pos;
      continue;
    }
    const std::uint64_t offset = pos_;
    pos_ += n;  // the next packet starts here whatever happens to this one
    ++packets_;

    packet.header_type = h.HeaderType;
    packet.offset = offset;
    packet.size_bytes = h.NumBytesThisRecord;
    packet.index = current_packet_;
    const auto too_small = [&](std::size_t need, const char* record) {
      report(AnomalyKind::kBadRecordSize, offset,
             std::string("xtf reader: NumBytesThisRecord = ") + std::to_string(n) + at(offset, nm) +
                 " is smaller than the " + std::to_string(need) + "-byte " + record +
                 "; packet skipped");
    };
    // Decodes the packet's fixed-size record into `record`; false (reported) if it is smaller.
    const auto read_record = [&](auto& record, const char* record_name) {
      constexpr std::size_t kSize = std::remove_reference_t<decltype(record)>::kSize;
      if (n < kSize) {
        too_small(kSize, record_name);
        return false;
      }
      buffer_.resize(kSize);
      source_->read(offset, buffer_);
      ByteReader r(buffer_);
      record = std::remove_reference_t<decltype(record)>::decode(r);
      return true;
    };
    switch (h.HeaderType) {
      case static_cast<std::uint8_t>(HeaderType::kSonar): {
        ++sonar_packets_;
        if (n < XtfPingHeader::kSize) {
          too_small(XtfPingHeader::kSize, "XTFPINGHEADER");
          continue;
        }
        if (n > options_.max_packet_bytes) {
          report(AnomalyKind::kOversizedPacket, offset,
                 "xtf reader: sonar packet of " + std::to_string(n) + " bytes" + at(offset, nm) +
                     " exceeds max_packet_bytes = " + std::to_string(options_.max_packet_bytes) +
                     "; skipped");
          continue;
        }
        buffer_.resize(static_cast<std::size_t>(n));
        source_->read(offset, buffer_);
        if (!decode_ping(buffer_, offset, packet.ping)) continue;
        packet.kind = PacketKind::kPing;
        return true;
      }
      case static_cast<std::uint8_t>(HeaderType::kNotes):
        if (!read_record(packet.notes, "XTFNOTESHEADER")) continue;
        packet.kind = PacketKind::kNotes;
        return true;
      case static_cast<std::uint8_t>(HeaderType::kAttitude):
        if (!read_record(packet.attitude, "XTFATTITUDEDATA")) continue;
        packet.kind = PacketKind::kAttitude;
        return true;
      case static_cast<std::uint8_t>(HeaderType::kNavigation):
        if (!read_record(packet.navigation, "XTFHEADERNAVIGATION")) continue;
        packet.kind = PacketKind::kNavigation;
        return true;
      default:
        packet.kind = PacketKind::kOther;  // unknown or unused type: skipped without reading
        return true;
    }
  }
  return false;
}

std::string Reader::ping_where(std::uint32_t ping_number, std::uint64_t offset) const {
  return " (packet " + std::to_string(current_packet_) + ", sonar packet " +
         std::to_string(sonar_packets_ - 1) + ", PingNumber " + std::to_string(ping_number) + ")" +
         at(offset, source_->name());
}

bool Reader::decode_ping(std::span<const std::uint8_t> bytes, std::uint64_t offset,
                         PingRecord& ping) {
  ByteReader r(bytes);
  ping.header = XtfPingHeader::decode(r);
  const std::uint32_t ping_number = ping.header.PingNumber;
  const std::size_t nchan = ping.header.Header.NumChansToFollow;
  // Each channel needs at least its 64-byte header: a count the record cannot hold is rejected
  // before anything is allocated for it.
  if (nchan > r.remaining() / XtfPingChanHeader::kSize) {
    report(AnomalyKind::kBadRecordSize, offset,
           "xtf reader: NumChansToFollow = " + std::to_string(nchan) +
               ping_where(ping_number, offset) + " does not fit in NumBytesThisRecord = " +
               std::to_string(bytes.size()) + "; ping skipped");
    return false;
  }
  if (ping.channels.size() < nchan) ping.channels.resize(nchan);
  ping.channel_count = 0;
  for (std::size_t i = 0; i < nchan; ++i) {
    // The samples of the channels before may have used the room the count check assumed.
    if (r.remaining() < XtfPingChanHeader::kSize) {
      report(AnomalyKind::kBadRecordSize, offset,
             "xtf reader: NumChansToFollow = " + std::to_string(nchan) +
                 ping_where(ping_number, offset) + " but the header of channel " +
                 std::to_string(i) + " would start at record byte " + std::to_string(r.position()) +
                 ", past NumBytesThisRecord = " + std::to_string(bytes.size()) +
                 " less its 64 bytes; ping skipped");
      return false;
    }
    ChannelData& ch = ping.channels[i];
    ch.header = XtfPingChanHeader::decode(r);
    const std::uint16_t number = ch.header.ChannelNumber;
    if (number >= chan_info_.size()) {
      report(AnomalyKind::kBadChannel, offset,
             "xtf reader: ChannelNumber = " + std::to_string(number) +
                 ping_where(ping_number, offset) + " but the file has " +
                 std::to_string(chan_info_.size()) + " CHANINFO; ping skipped");
      return false;
    }
    const XtfChanInfo& info = chan_info_[number];
    std::uint16_t bps = 0;
    const SampleKind kind = sample_kind(info, options_.signedness, bps);
    if (kind == SampleKind::kUnsupported || bps == 0) {
      report(AnomalyKind::kBadChannel, offset,
             "xtf reader: CHANINFO[" + std::to_string(number) +
                 "] has SampleFormat = " + std::to_string(info.SampleFormat) +
                 ", BytesPerSample = " + std::to_string(info.BytesPerSample) +
                 " (unsupported), used" + ping_where(ping_number, offset) + "; ping skipped");
      return false;
    }
    std::uint64_t samples = ch.header.NumSamples;
    if (samples == 0) samples = info.Reserved;  // old readers' fallback to SamplesPerChannel
    const std::uint64_t need = samples * bps;   // <= 2^32 * 4: no overflow in 64 bits
    if (need > r.remaining()) {
      report(AnomalyKind::kSamplesBeyondRecord, offset,
             "xtf reader: channel " + std::to_string(number) +
                 " NumSamples = " + std::to_string(ch.header.NumSamples) + " x " +
                 std::to_string(bps) + " bytes" + ping_where(ping_number, offset) +
                 " runs past NumBytesThisRecord = " + std::to_string(bytes.size()) +
                 "; ping skipped");
      return false;
    }
    ch.type_of_channel = info.TypeOfChannel;
    ch.samples.resize(static_cast<std::size_t>(samples));
    convert_samples(bytes.data() + r.position(), ch.samples.size(), kind, ch.samples.data());
    r.skip(static_cast<std::size_t>(need));
    if (info.TypeOfChannel == static_cast<std::uint8_t>(ChannelType::kPort)) {
      std::reverse(ch.samples.begin(), ch.samples.end());  // stored far -> near
    }
    ping.channel_count = i + 1;
  }
  normalise(ping, offset);
  return true;
}

void Reader::normalise(PingRecord& ping, std::uint64_t offset) {
  const std::string& nm = source_->name();
  const XtfPingHeader& h = ping.header;
  SonarPing& s = ping.sonar;

  const auto t = h.HSeconds < 100
                     ? calendar::time_from_fields(h.Year, h.Month, h.Day, h.Hour, h.Minute,
                                                  h.Second, std::uint32_t{h.HSeconds} * 10000u)
                     : std::nullopt;
  ping.time_valid = t.has_value();
  s.time_utc = t.value_or(UtcTime{});
  if (!t) {
    report(AnomalyKind::kInvalidTime, offset,
           "xtf reader: ping " + std::to_string(h.PingNumber) + at(offset, nm) +
               " has an invalid time " + std::to_string(h.Year) + "-" + std::to_string(h.Month) +
               "-" + std::to_string(h.Day) + " " + std::to_string(h.Hour) + ":" +
               std::to_string(h.Minute) + ":" + std::to_string(h.Second) + "." +
               std::to_string(h.HSeconds));
  } else {
    if (have_last_time_ && *t < last_time_) {
      report(AnomalyKind::kTimeBackwards, offset,
             "xtf reader: ping " + std::to_string(h.PingNumber) + at(offset, nm) +
                 " is earlier than the previous ping");
    }
    have_last_time_ = true;
    last_time_ = *t;
  }

  const double x = h.SensorXcoordinate;
  const double y = h.SensorYcoordinate;
  const bool geographic = header_.NavUnits == 3;
  ping.nav_valid = std::isfinite(x) && std::isfinite(y) && x != 0.0 && y != 0.0 &&
                   (!geographic || (std::abs(x) <= 180.0 && std::abs(y) <= 90.0));
  if (!ping.nav_valid) {
    std::ostringstream os;
    os.precision(10);
    os << "xtf reader: ping " << h.PingNumber << at(offset, nm)
       << " has no usable sensor position (SensorXcoordinate = " << x
       << ", SensorYcoordinate = " << y << "); flagged, not trusted";
    report(AnomalyKind::kZeroNavigation, offset, os.str());
  }
  s.ping_number = h.PingNumber;
  s.sensor_position =
      ping.nav_valid && geographic ? Geodetic{rad_from_deg(y), rad_from_deg(x), 0.0} : Geodetic{};
  const double sx = h.ShipXcoordinate;
  const double sy = h.ShipYcoordinate;
  if (geographic && std::isfinite(sx) && std::isfinite(sy) && sx != 0.0 && sy != 0.0 &&
      std::abs(sx) <= 180.0 && std::abs(sy) <= 90.0) {
    s.ship_position = Geodetic{rad_from_deg(sy), rad_from_deg(sx), 0.0};
  } else {
    s.ship_position.reset();
  }
  s.heading_true_rad = rad_from_deg(h.SensorHeading);
  s.pitch_rad = rad_from_deg(h.SensorPitch);
  s.roll_rad = rad_from_deg(h.SensorRoll);
  s.heave_m = h.Heave;
  s.altitude_m = h.SensorPrimaryAltitude;
  s.depth_m = h.SensorDepth;
  s.speed_m_s = static_cast<double>(h.SensorSpeed) * kMetresPerSecondPerKnot;
  // Full speed of sound: ComputedSoundVelocity when it looks like one, else SoundVelocity,
  // doubled when it is the one-way ("half", ~750) value most writers store.
  const double csv = h.ComputedSoundVelocity;
  const double sv = h.SoundVelocity;
  s.sound_speed_m_s =
      (csv > 1000.0 && csv < 2000.0) ? csv : (sv > 0.0 && sv < 1000.0 ? 2 * sv : sv);
  s.slant_range_m = 0.0;
  s.port.clear();
  s.starboard.clear();
  bool have_port = false;
  bool have_stbd = false;
  for (std::size_t i = 0; i < ping.channel_count; ++i) {
    const ChannelData& ch = ping.channels[i];
    if (!have_port && ch.type_of_channel == static_cast<std::uint8_t>(ChannelType::kPort)) {
      s.port.assign(ch.samples.begin(), ch.samples.end());
      s.slant_range_m = std::max(s.slant_range_m, static_cast<double>(ch.header.SlantRange));
      have_port = true;
    } else if (!have_stbd &&
               ch.type_of_channel == static_cast<std::uint8_t>(ChannelType::kStarboard)) {
      s.starboard.assign(ch.samples.begin(), ch.samples.end());
      s.slant_range_m = std::max(s.slant_range_m, static_cast<double>(ch.header.SlantRange));
      have_stbd = true;
    }
  }
}

}  // namespace sonarsynth::xtf
