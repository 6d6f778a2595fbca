// SPDX-License-Identifier: MIT
// The bag readers' ping assembly (docs/rosbag.md and docs/robotics.md, "Reading bags"): the
// sides paired by header.stamp, the navigation and attitude at or before each ping.
#include "sonarsynth/formats/rosbag/ping_assembler.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::rosbag {
namespace {

constexpr std::size_t kMaxPending = 4096;  // unpaired image stamps kept before giving up on one

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

/// +1 port, -1 starboard, 0 neither: from the frame id, else from the topic.
int side_of(std::string_view frame, std::string_view topic) {
  for (const std::string& s : {lower(frame), lower(topic)}) {
    if (s.find("port") != std::string::npos) return 1;
    if (s.find("starboard") != std::string::npos || s.find("stbd") != std::string::npos) return -1;
  }
  return 0;
}

/// The element of `v` (sorted by stamp, ordinal) with the latest stamp <= `stamp`. Of several
/// with that stamp: with kAfterImages the first written after `ordinal`, else the last; with
/// kBeforeImages the last written before `ordinal`, else the first.
template <class T>
T* at_or_before(std::vector<T>& v, std::uint64_t stamp, std::uint64_t ordinal,
                PingAssembler::NavOrder order) {
  auto it = std::upper_bound(v.begin(), v.end(), stamp,
                             [](std::uint64_t s, const T& e) { return s < e.stamp_ns; });
  if (it == v.begin()) return nullptr;
  const std::uint64_t s = std::prev(it)->stamp_ns;
  auto first = std::lower_bound(v.begin(), it, s,
                                [](const T& e, std::uint64_t t) { return e.stamp_ns < t; });
  if (order == PingAssembler::NavOrder::kAfterImages) {
    for (auto k = first; k != it; ++k) {
      if (k->ordinal > ordinal) return &*k;
    }
    return &*std::prev(it);
  }
  for (auto k = it; k != first; --k) {
    if (std::prev(k)->ordinal < ordinal) return &*std::prev(k);
  }
  return &*first;
}

}  // namespace

bool names_port(std::string_view frame) {
  return lower(frame).find("port") != std::string::npos;
}

PingAssembler::PingAssembler(std::string prefix, NavOrder order, Report report)
    : prefix_(std::move(prefix)), order_(order), report_(std::move(report)) {}

void PingAssembler::add_fix(std::uint64_t stamp_ns, std::uint64_t ordinal, std::int8_t status,
                            double lat_deg, double lon_deg) {
  Fix f{stamp_ns, ordinal, {}, false};
  f.valid = status >= 0 && std::abs(lat_deg) <= 90.0 && std::abs(lon_deg) <= 180.0 &&
            (lat_deg != 0.0 || lon_deg != 0.0);
  if (f.valid) f.position = {rad_from_deg(lat_deg), rad_from_deg(lon_deg), 0.0};
  fixes_.push_back(f);
}

void PingAssembler::sort() {
  const auto by_stamp = [](const auto& a, const auto& b) {
    return a.stamp_ns != b.stamp_ns ? a.stamp_ns < b.stamp_ns : a.ordinal < b.ordinal;
  };
  std::sort(fixes_.begin(), fixes_.end(), by_stamp);
  std::sort(imu_.begin(), imu_.end(), by_stamp);
}

void PingAssembler::add_image(const ImageFields& f, const ImageSource& source) {
  Side side;
  side.offset = source.offset;
  side.ordinal = source.ordinal;
  side.number = source.number;
  side.dtype = f.info.dtype;
  side.sound_speed_m_s = f.sound_speed_m_s;
  const std::string where = prefix_ + "byte " + std::to_string(source.offset) + ": ";
  const auto bad = [&](const std::string& what) {
    report_(source.offset, where + std::string(source.type) + " (" + std::string(source.topic) +
                               ") " + what + "; skipped");
  };
  const std::uint32_t n = f.samples_per_beam;
  const double rate = f.sample_rate_hz;
  if (side.dtype >= records::kDtypeBytes.size()) {
    return bad("image.dtype = " + std::to_string(side.dtype) + ": unknown (0..9)");
  }
  if (f.beam_count != 1) {
    return bad("image.beam_count = " + std::to_string(f.beam_count) +
               ": one beam per side expected");
  }
  if (n == 0 || f.data.size() != std::size_t{n} * records::kDtypeBytes[side.dtype]) {
    return bad("image.data has " + std::to_string(f.data.size()) +
               " bytes for samples_per_beam = " + std::to_string(n));
  }
  if (!(rate > 0.0) || !std::isfinite(rate)) {
    return bad("sample_rate = " + std::to_string(rate) + ": not > 0");
  }
  const int which = side_of(source.frame, source.topic);
  if (which == 0) {
    return bad("header.frame_id = '" + std::string(source.frame) +
               "': neither port nor starboard (frame id or topic)");
  }
  if (!(side.sound_speed_m_s > 0.0) || !std::isfinite(side.sound_speed_m_s)) {
    report_(source.offset, where + "ping_info.sound_speed = " +
                               std::to_string(side.sound_speed_m_s) + ": 1500 m/s assumed");
    side.sound_speed_m_s = 1500.0;
  }
  side.slant_range_m = n * side.sound_speed_m_s / (2.0 * rate);
  records::decode_samples(f.data, side.dtype, f.big_endian, side.samples);
  side.present = true;
  add_side(std::move(side), which > 0, source.stamp_ns);
}

void PingAssembler::unpaired(const Side& s, std::uint64_t stamp_ns) {
  report_(s.offset, prefix_ + "byte " + std::to_string(s.offset) +
                        ": image without its other side (header.stamp " + std::to_string(stamp_ns) +
                        " ns); skipped");
}

void PingAssembler::add_side(Side side, bool port, std::uint64_t stamp_ns) {
  auto& pair = pending_[stamp_ns];
  Side& slot = port ? pair.first : pair.second;
  if (slot.present) {
    report_(slot.offset, prefix_ + "byte " + std::to_string(slot.offset) + ": a second " +
                             (port ? "port" : "starboard") +
                             " image of the same header.stamp; the first skipped");
  }
  slot = std::move(side);
  if (pair.first.present && pair.second.present) complete(stamp_ns);
  while (pending_.size() > kMaxPending) {
    const auto oldest = pending_.begin();
    unpaired(oldest->second.first.present ? oldest->second.first : oldest->second.second,
             oldest->first);
    pending_.erase(oldest);
  }
}

void PingAssembler::complete(std::uint64_t stamp_ns) {
  auto node = pending_.extract(stamp_ns);
  Side& port = node.mapped().first;
  Side& stbd = node.mapped().second;
  Ping p;
  p.sonar.time_utc = utc_from_ns(stamp_ns);
  p.sonar.ping_number = port.number;
  p.sonar.sound_speed_m_s = port.sound_speed_m_s;
  p.sonar.slant_range_m = port.slant_range_m;
  const double port_step = port.slant_range_m / static_cast<double>(port.samples.size());
  const double stbd_step = stbd.slant_range_m / static_cast<double>(stbd.samples.size());
  if (std::abs(stbd_step - port_step) > 1e-6 * port_step) {
    report_(stbd.offset, prefix_ + "byte " + std::to_string(stbd.offset) +
                             ": starboard sample spacing differs from port's; port's used");
  }
  p.sonar.port = std::move(port.samples);
  p.sonar.starboard = std::move(stbd.samples);
  p.offset = port.offset;
  p.index = port.ordinal;
  p.dtype = port.dtype;
  // The navigation of the ping's stamp is written after its images (ROS 1) or before (MCAP).
  const std::uint64_t ordinal = order_ == NavOrder::kAfterImages
                                    ? std::max(port.ordinal, stbd.ordinal)
                                    : std::min(port.ordinal, stbd.ordinal);
  if (const Fix* f = at_or_before(fixes_, stamp_ns, ordinal, order_); f && f->valid) {
    p.sonar.sensor_position = f->position;
    p.nav_valid = true;
  }
  if (ImuSample* s = at_or_before(imu_, stamp_ns, ordinal, order_); s && s->known) {
    p.sonar.heading_true_rad = s->attitude.heading_true_rad;
    p.sonar.pitch_rad = s->attitude.pitch_rad;
    p.sonar.roll_rad = s->attitude.roll_rad;
    p.attitude_valid = true;
    s->used = true;
  }
  ready_.push_back(std::move(p));
}

bool PingAssembler::pop(Ping& ping) {
  if (ready_.empty()) return false;
  ping = std::move(ready_.front());
  ready_.pop_front();
  return true;
}

void PingAssembler::finish() {
  for (const auto& [stamp, pair] : pending_) {
    unpaired(pair.first.present ? pair.first : pair.second, stamp);
  }
  pending_.clear();
}

}  // namespace sonarsynth::rosbag
