// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/jsf/reader.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <sstream>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/time_fields.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::jsf {
namespace {

constexpr double kMetresPerSecondPerKnot = 1852.0 / 3600.0;
constexpr std::size_t kScanChunk = 1 << 16;

std::string num(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

}  // namespace

const char* anomaly_kind_name(AnomalyKind kind) {
  // In AnomalyKind order.
  static constexpr const char* kNames[] = {
      "garbage_skipped",  "bad_byte_count",      "oversized_message",    "bad_sonar_data",
      "unpaired_channel", "invalid_time",        "time_backwards",       "zero_navigation",
      "other_subsystem",  "sound_speed_assumed", "bad_weighting_factor", "bad_range"};
  static_assert(std::size(kNames) == kAnomalyKindCount);
  const auto k = static_cast<std::size_t>(kind);
  return k < kAnomalyKindCount ? kNames[k] : "unknown";
}

void ReaderOptions::validate() const {
  if (max_message_bytes < 256) {
    throw InputError("jsf reader: max_message_bytes = " + std::to_string(max_message_bytes) +
                     ". Violated constraint: >= 256");
  }
  if (subsystem < -1 || subsystem > 255) {
    throw InputError("jsf reader: subsystem = " + std::to_string(subsystem) +
                     ". Violated constraint: -1 (first side scan) or 0..255");
  }
}

Reader::Reader(const std::filesystem::path& path, ReaderOptions options)
    : Reader(xtf::open_file_source(path), options) {}

Reader::Reader(std::span<const std::uint8_t> bytes, std::string name, ReaderOptions options)
    : Reader(xtf::memory_source(bytes, std::move(name)), options) {}

Reader::Reader(std::unique_ptr<ByteSource> source, ReaderOptions options)
    : source_(std::move(source)), options_((options.validate(), options)) {
  open();
}

Reader::~Reader() = default;

const std::string& Reader::name() const {
  return source_->name();
}

void Reader::open() {
  size_ = source_->size();
  if (size_ < MessageHeader::kSize) {
    throw FormatError("jsf reader: " + name() + ": " + std::to_string(size_) +
                      " bytes, shorter than one 16-byte JSF message header: not a JSF file");
  }
  std::array<std::uint8_t, 2> first{};
  source_->read(0, first);
  if (first[0] != 0x01 || first[1] != 0x16) {
    std::ostringstream os;
    os << "jsf reader: " << name() << ": starts with bytes 0x" << std::hex
       << static_cast<int>(first[0]) << " 0x" << static_cast<int>(first[1])
       << ", not the JSF message start marker 0x1601 (bytes 01 16): not a JSF file";
    throw FormatError(os.str());
  }
}

void Reader::report(AnomalyKind kind, std::uint64_t offset, std::string message) {
  log_anomaly({kind, offset, std::move(message), messages_}, options_.max_anomaly_messages);
}

bool Reader::plausible_header_at(std::uint64_t offset, MessageHeader& header) {
  if (offset > size_ || size_ - offset < MessageHeader::kSize) return false;
  std::array<std::uint8_t, MessageHeader::kSize> bytes{};
  source_->read(offset, bytes);
  ByteReader r(bytes, "jsf");
  header = MessageHeader::decode(r);
  return header.start_marker == kStartMarker && header.byte_count >= 0 &&
         static_cast<std::uint64_t>(header.byte_count) <= size_ - offset - MessageHeader::kSize;
}

std::uint64_t Reader::find_next_message(std::uint64_t from) {
  MessageHeader h;
  std::uint64_t chunk_start = from;
  while (chunk_start + 1 < size_) {
    const std::uint64_t n = std::min<std::uint64_t>(kScanChunk, size_ - chunk_start);
    scan_buffer_.resize(static_cast<std::size_t>(n));
    source_->read(chunk_start, scan_buffer_);
    for (std::size_t i = 0; i + 1 < scan_buffer_.size(); ++i) {
      if (scan_buffer_[i] == 0x01 && scan_buffer_[i + 1] == 0x16 &&
          plausible_header_at(chunk_start + i, h)) {
        return chunk_start + i;
      }
    }
    chunk_start += n - 1;  // the last byte may start a marker split over two chunks
    if (n < 2) break;
  }
  return size_;
}

std::string Reader::where(const Message& m) const {
  return " (message " + std::to_string(m.index) + ", type " +
         std::to_string(m.header.message_type) + ", subsystem " +
         std::to_string(m.header.subsystem) + ", channel " + std::to_string(m.header.channel) +
         ") at byte " + std::to_string(m.offset) + " of " + name();
}

bool Reader::next(Message& m) {
  while (pos_ < size_) {
    MessageHeader h;
    if (!plausible_header_at(pos_, h)) {
      const bool marker = h.start_marker == kStartMarker && size_ - pos_ >= MessageHeader::kSize;
      const std::uint64_t next = find_next_message(pos_ + 1);
      if (marker) {
        report(AnomalyKind::kBadByteCount, pos_,
               "jsf reader: message at byte " + std::to_string(pos_) + " of " + name() +
                   " announces " + std::to_string(h.byte_count) + " bytes but " +
                   std::to_string(size_ - pos_ - MessageHeader::kSize) +
                   " remain after its header (truncated file or corrupted byte count); " +
                   std::to_string(next - pos_) + " bytes skipped");
      } else {
        report(AnomalyKind::kGarbageSkipped, pos_,
               "jsf reader: " + std::to_string(next - pos_) + " bytes at byte " +
                   std::to_string(pos_) + " of " + name() +
                   " are not a JSF message (no 0x1601 start marker); skipped");
      }
      pos_ = next;
      continue;
    }
    const std::uint64_t body = static_cast<std::uint64_t>(h.byte_count);
    m.kind = MessageKind::kOther;
    m.header = h;
    m.offset = pos_;
    m.index = messages_;
    pos_ += MessageHeader::kSize + body;
    ++messages_;
    ++counts_[h.message_type];
    if (body > options_.max_message_bytes) {
      report(AnomalyKind::kOversizedMessage, m.offset,
             "jsf reader: byte count " + std::to_string(body) + " exceeds max_message_bytes " +
                 std::to_string(options_.max_message_bytes) + where(m) + "; skipped");
      return true;
    }
    const auto type = static_cast<MessageType>(h.message_type);
    const bool wanted = type == MessageType::kSonarData ||
                        type == MessageType::kSystemInformation ||
                        type == MessageType::kPitchRoll || type == MessageType::kSonarsynthXtfPing;
    if (!wanted) return true;
    buffer_.resize(static_cast<std::size_t>(body));
    source_->read(m.offset + MessageHeader::kSize, buffer_);
    ByteReader r(buffer_, "jsf");
    if (type == MessageType::kSonarData) {
      ++sonar_counts_[h.subsystem][h.channel];
      if (decode_sonar(buffer_, m)) m.kind = MessageKind::kSonar;
    } else if (type == MessageType::kSystemInformation) {
      if (body >= SystemInformation::kSize) {
        m.system = SystemInformation::decode(r);
        m.kind = MessageKind::kSystemInformation;
        if (!system_) {
          system_ = m.system;
          XtfFileFields f;
          if (body >= SystemInformation::kSize + XtfFileFields::kSize &&
              XtfFileFields::decode(r, f)) {
            xtf_file_ = f;
          }
        }
      }
    } else if (type == MessageType::kSonarsynthXtfPing) {
      if (body >= XtfPingFields::kSize && XtfPingFields::decode(r, m.xtf_ping)) {
        m.kind = MessageKind::kXtfPingFields;
      }
    } else if (body >= 44) {
      const std::int32_t s = r.i32();
      const std::int32_t ms = r.i32();
      r.skip(4 + 12);
      AttitudeSample& a = m.attitude;
      a.time_utc =
          UtcTime{std::chrono::seconds{s}} + std::chrono::milliseconds{std::clamp(ms, 0, 999)};
      a.pitch_rad = rad_from_deg(r.i16() * 180.0 / 32768.0);
      a.roll_rad = rad_from_deg(r.i16() * 180.0 / 32768.0);
      r.skip(4);
      a.heave_m = -r.i16() / 1000.0;
      a.heading_true_rad = rad_from_deg(r.u16() / 100.0);
      r.skip(4);
      a.yaw_rad = rad_from_deg(r.i16() / 100.0);
      m.kind = MessageKind::kPitchRoll;
    }
    return true;
  }
  return false;
}

bool Reader::decode_sonar(std::span<const std::uint8_t> body, Message& m) {
  if (body.size() < SonarDataHeader::kSize) {
    report(AnomalyKind::kBadSonarData, m.offset,
           "jsf reader: sonar data message of " + std::to_string(body.size()) +
               " bytes, shorter than its 240-byte header" + where(m));
    return false;
  }
  ByteReader r(body, "jsf");
  m.sonar = SonarDataHeader::decode(r);
  const SonarDataHeader& h = m.sonar;
  const std::int16_t f = h.data_format;
  if (f < 0 || f > 9 || (f > 4 && f != 9)) {
    report(AnomalyKind::kBadSonarData, m.offset,
           "jsf reader: data format " + std::to_string(f) +
               " is not 0, 1, 2, 3, 4 or 9 (proprietary or unknown samples)" + where(m));
    return false;
  }
  const std::uint64_t n = h.sample_count();
  const std::uint64_t k = h.values_per_sample();
  const std::uint64_t need = SonarDataHeader::kSize + 2 * k * n;
  if (need > body.size()) {
    report(AnomalyKind::kBadSonarData, m.offset,
           "jsf reader: " + std::to_string(n) + " samples of data format " + std::to_string(f) +
               " need " + std::to_string(need) + " bytes but the byte count is " +
               std::to_string(body.size()) + where(m));
    return false;
  }
  m.samples.resize(static_cast<std::size_t>(n));
  const std::uint8_t* p = body.data() + SonarDataHeader::kSize;
  const double scale = std::ldexp(1.0, -h.weighting_factor);  // exact: a power of two
  float* out = m.samples.data();
  if (k == 2) {
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint8_t* s = p + i * 4;
      const auto re = static_cast<std::int16_t>(s[0] | (s[1] << 8));
      const auto im = static_cast<std::int16_t>(s[2] | (s[3] << 8));
      out[i] =
          static_cast<float>(std::hypot(static_cast<double>(re), static_cast<double>(im)) * scale);
    }
  } else if (f == 0) {  // envelope: unsigned
    for (std::size_t i = 0; i < n; ++i) {
      const auto v = static_cast<std::uint16_t>(p[2 * i] | (p[2 * i + 1] << 8));
      out[i] = static_cast<float>(static_cast<double>(v) * scale);
    }
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      const auto v = static_cast<std::int16_t>(p[2 * i] | (p[2 * i + 1] << 8));
      out[i] = static_cast<float>(static_cast<double>(v) * scale);
    }
  }
  // Stored values are below 2^17 in magnitude: for -111 <= N <= 126 every one scales to a
  // normal float exactly. Beyond, count the nonzero ones that became 0 or infinite.
  const int wf = h.weighting_factor;
  if (wf < -111 || wf > 126) {
    std::uint64_t lost = 0, nonzero = 0;
    for (std::size_t i = 0; i < n * k; ++i) {
      if ((p[2 * i] | p[2 * i + 1]) == 0) continue;
      ++nonzero;
      const float v = out[i / k];
      lost += (v == 0.0f || !std::isfinite(v)) ? 1 : 0;
    }
    if (lost > 0) {
      report(AnomalyKind::kBadWeighting, m.offset,
             "jsf reader: weighting factor " + std::to_string(wf) + ": samples x 2^" +
                 std::to_string(-wf) + " do not fit a float (" + std::to_string(lost) + " of " +
                 std::to_string(nonzero) +
                 " nonzero stored values became 0 or infinite; writers use -200..200, real files "
                 "0..16)" +
                 where(m));
    }
  }
  return true;
}

void Reader::make_ping(Message* port, Message* stbd, Ping& ping) {
  const Message& first = port ? *port : *stbd;
  const SonarDataHeader& h = first.sonar;
  ping.subsystem = first.header.subsystem;
  ping.offset = first.offset;
  ping.index = first.index;
  ping.header = h;
  SonarPing& s = ping.sonar;
  s.ping_number = h.ping_number;
  // The messages' sample buffers are not read again: swap them in (capacity is recycled).
  s.port.clear();
  s.starboard.clear();
  if (port) std::swap(s.port, port->samples);
  if (stbd) std::swap(s.starboard, stbd->samples);

  // Time: offset 0 + ms today % 1000 (protocol >= 8), else the CPU-time block.
  using namespace std::chrono;
  const milliseconds frac{h.ms_today % 1000};
  std::optional<UtcTime> t;
  if (first.header.protocol_version >= 8 && h.ping_time_s > 0) {
    t = UtcTime{seconds{h.ping_time_s}} + frac;
  } else if (h.year >= 1 && h.day_of_year >= 1 && h.day_of_year <= 366 && h.hour >= 0 &&
             h.minute >= 0 && h.second >= 0) {
    const auto jan1 = calendar::time_from_fields(h.year, 1, 1, 0, 0, 0, 0);
    if (jan1 && h.hour <= 23 && h.minute <= 59 && h.second <= 60) {
      t = *jan1 + days{h.day_of_year - 1} + hours{h.hour} + minutes{h.minute} + seconds{h.second} +
          frac;
    }
  }
  ping.time_valid = t.has_value();
  if (t) {
    s.time_utc = *t;
    if (have_last_time_ && *t < last_time_) {
      report(AnomalyKind::kTimeBackwards, first.offset,
             "jsf reader: ping time goes backwards by " +
                 num(duration<double>(last_time_ - *t).count()) + " s" + where(first));
    }
    have_last_time_ = true;
    last_time_ = *t;
  } else {
    s.time_utc = {};
    report(AnomalyKind::kInvalidTime, first.offset,
           "jsf reader: no valid ping time (ping time " + std::to_string(h.ping_time_s) +
               " s, CPU time year " + std::to_string(h.year) + " day " +
               std::to_string(h.day_of_year) + ")" + where(first));
  }

  const double lon = h.longitude / kCoordinatePerDegree;
  const double lat = h.latitude / kCoordinatePerDegree;
  ping.nav_valid = h.coordinate_units == kUnitsMinutesOfArc &&
                   !(h.longitude == 0 && h.latitude == 0) && std::abs(lon) <= 180.0 &&
                   std::abs(lat) <= 90.0;
  s.sensor_position = {rad_from_deg(lat), rad_from_deg(lon), 0.0};
  s.ship_position.reset();
  if (!ping.nav_valid) {
    report(AnomalyKind::kZeroNavigation, first.offset,
           "jsf reader: no position (longitude " + std::to_string(h.longitude) + ", latitude " +
               std::to_string(h.latitude) + ", coordinate units " +
               std::to_string(h.coordinate_units) + "; readable: units 2, not both 0)" +
               where(first));
  }
  s.heading_true_rad = rad_from_deg(h.heading_cdeg / 100.0);
  s.pitch_rad = rad_from_deg(h.pitch * 180.0 / 32768.0);
  s.roll_rad = rad_from_deg(h.roll * 180.0 / 32768.0);
  s.heave_m = -static_cast<double>(h.heave_m);
  s.altitude_m = h.altitude_mm / 1000.0;
  s.depth_m = h.depth_mm / 1000.0;
  double speed_kn = h.speed_dkn / 10.0;
  if (first.header.protocol_version >= 0xC) speed_kn += (h.lsb2 & 0xFu) / 100.0;
  s.speed_m_s = speed_kn * kMetresPerSecondPerKnot;
  const bool c_valid = std::isfinite(h.sound_speed_m_s) && h.sound_speed_m_s > 0.0f;
  const double c = c_valid ? static_cast<double>(h.sound_speed_m_s) : kAssumedSoundSpeed_m_s;
  if (!c_valid) {
    report(AnomalyKind::kSoundSpeedAssumed, first.offset,
           "jsf reader: ping " + std::to_string(h.ping_number) + ": sound speed " +
               num(h.sound_speed_m_s) + " m/s is not a speed; " + num(c) +
               " m/s assumed for the slant range" + where(first));
  }
  s.sound_speed_m_s = c;
  const std::size_t n = std::max(s.port.size(), s.starboard.size());
  s.slant_range_m = c * static_cast<double>(n) * h.sample_interval_ns * 1e-9 / 2.0;
  if (n > 0 && (h.sample_interval_ns == 0 || s.slant_range_m > kMaxPlausibleSlantRange_m)) {
    report(AnomalyKind::kBadRange, first.offset,
           "jsf reader: ping " + std::to_string(h.ping_number) + ": sample interval " +
               std::to_string(h.sample_interval_ns) + " ns x " + std::to_string(n) +
               " samples gives a slant range of " + num(s.slant_range_m) + " m (" +
               (h.sample_interval_ns == 0 ? std::string("no sample spacing")
                                          : "over " + num(kMaxPlausibleSlantRange_m) +
                                                " m: implausible for a side-scan sonar") +
               ")" + where(first));
  }
  ping.layback_m = std::isfinite(h.layback_m) ? static_cast<double>(h.layback_m) : 0.0;
}

bool Reader::next_ping(Ping& ping) {
  if (!assemble_ping(ping)) return false;
  ping.xtf_fields.reset();
  if (carried_ && carried_->ping.PingNumber == ping.sonar.ping_number) {
    ping.xtf_fields = std::move(carried_);
    carried_.reset();
  }
  return true;
}

bool Reader::assemble_ping(Ping& ping) {
  while (next(current_)) {
    if (current_.kind == MessageKind::kXtfPingFields) carried_ = current_.xtf_ping;
    if (current_.kind != MessageKind::kSonar) continue;
    const int sub = current_.header.subsystem;
    if (subsystem_ < 0) {
      if (options_.subsystem >= 0) {
        subsystem_ = options_.subsystem;
      } else if (sub >= kSubsystemSideScanLow && sub <= kSubsystemSideScanVeryHigh) {
        subsystem_ = sub;
      }
    }
    if (sub != subsystem_) {
      if (subsystem_ >= 0 && anomaly_count(AnomalyKind::kOtherSubsystem) == 0) {
        report(AnomalyKind::kOtherSubsystem, current_.offset,
               "jsf reader: sonar data of subsystem " + std::to_string(sub) +
                   " ignored (pings are read from subsystem " + std::to_string(subsystem_) +
                   "; reported once)" + where(current_));
      }
      continue;
    }
    const std::uint8_t ch = current_.header.channel;
    if (ch == kChannelPort) {
      if (have_pending_) {
        report(AnomalyKind::kUnpairedChannel, pending_.offset,
               "jsf reader: port message without a starboard one" + where(pending_));
        make_ping(&pending_, nullptr, ping);
        std::swap(pending_, current_);
        return true;
      }
      std::swap(pending_, current_);
      have_pending_ = true;
      continue;
    }
    if (ch != kChannelStarboard) continue;  // a third channel of a side-scan subsystem
    if (have_pending_ && pending_.sonar.ping_number == current_.sonar.ping_number) {
      have_pending_ = false;
      make_ping(&pending_, &current_, ping);
      return true;
    }
    report(AnomalyKind::kUnpairedChannel, current_.offset,
           "jsf reader: starboard message without a port one of ping number " +
               std::to_string(current_.sonar.ping_number) + where(current_));
    make_ping(nullptr, &current_, ping);
    return true;
  }
  if (have_pending_) {
    have_pending_ = false;
    report(AnomalyKind::kUnpairedChannel, pending_.offset,
           "jsf reader: port message without a starboard one" + where(pending_));
    make_ping(&pending_, nullptr, ping);
    return true;
  }
  return false;
}

}  // namespace sonarsynth::jsf
