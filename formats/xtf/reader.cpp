// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/xtf/reader.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iterator>
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

/// The little-endian unsigned integer of sizeof(U) bytes at `b`.
template <class U>
U load_le(const std::uint8_t* b) {
  U v = 0;
  for (std::size_t k = 0; k < sizeof(U); ++k) v = static_cast<U>(v | (U{b[k]} << (8 * k)));
  return v;
}

/// Converts `n` samples of a channel's sample format at `p` to floats.
using SampleDecoder = void (*)(const std::uint8_t* p, std::size_t n, float* out);

/// Integers of type T.
template <class T>
void decode_integers(const std::uint8_t* p, std::size_t n, float* out) {
  for (std::size_t i = 0; i < n; ++i) {
    out[i] =
        static_cast<float>(static_cast<T>(load_le<std::make_unsigned_t<T>>(p + sizeof(T) * i)));
  }
}

void decode_ieee32(const std::uint8_t* p, std::size_t n, float* out) {
  for (std::size_t i = 0; i < n; ++i)
    out[i] = std::bit_cast<float>(load_le<std::uint32_t>(p + 4 * i));
}

void decode_ibm32(const std::uint8_t* p, std::size_t n, float* out) {
  for (std::size_t i = 0; i < n; ++i) out[i] = ibm_to_float(load_le<std::uint32_t>(p + 4 * i));
}

/// Integers of `bytes` bytes (1, 2 or 4); nullptr for another width.
SampleDecoder integer_decoder(std::size_t bytes, bool is_signed) {
  switch (bytes) {
    case 1:
      return is_signed ? &decode_integers<std::int8_t> : &decode_integers<std::uint8_t>;
    case 2:
      return is_signed ? &decode_integers<std::int16_t> : &decode_integers<std::uint16_t>;
    case 4:
      return is_signed ? &decode_integers<std::int32_t> : &decode_integers<std::uint32_t>;
    default:
      return nullptr;
  }
}

/// The decoder of a channel's samples and their width in `bytes`; nullptr if unsupported.
SampleDecoder sample_decoder(const XtfChanInfo& c, Signedness signedness, std::uint16_t& bytes) {
  const bool is_signed = signedness == Signedness::kSigned ||
                         (signedness == Signedness::kFromUniPolar && c.UniPolar == 0);
  bytes = 4;
  switch (static_cast<SampleFormatCode>(c.SampleFormat)) {
    case SampleFormatCode::kIbmFloat32:
      return decode_ibm32;
    case SampleFormatCode::kIeeeFloat32:
      return decode_ieee32;
    case SampleFormatCode::kInt32:
      return integer_decoder(4, is_signed);
    case SampleFormatCode::kInt16:
      bytes = 2;
      return integer_decoder(2, is_signed);
    case SampleFormatCode::kInt8:
      bytes = 1;
      return integer_decoder(1, is_signed);
    case SampleFormatCode::kLegacy:
      bytes = c.BytesPerSample;
      return integer_decoder(bytes, is_signed);
  }
  bytes = 0;
  return nullptr;
}

}  // namespace

const char* anomaly_kind_name(AnomalyKind kind) {
  // In AnomalyKind order.
  static constexpr const char* kNames[] = {
      "garbage_skipped",       "bad_record_size",  "truncated_packet",     "bad_channel",
      "samples_beyond_record", "oversized_packet", "header_channel_count", "invalid_time",
      "time_backwards",        "zero_navigation"};
  static_assert(std::size(kNames) == kAnomalyKindCount);
  const auto k = static_cast<std::size_t>(kind);
  return k < kAnomalyKindCount ? kNames[k] : "unknown";
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

void Reader::report(AnomalyKind kind, std::uint64_t offset, std::string message) {
  log_anomaly({kind, offset, std::move(message), current_packet_}, options_.max_anomaly_messages);
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
    const SampleDecoder decode = sample_decoder(info, options_.signedness, bps);
    if (decode == nullptr || bps == 0) {
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
    decode(bytes.data() + r.position(), ch.samples.size(), ch.samples.data());
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
