// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/xtf/summary.hpp"

#include <cmath>
#include <cstdio>

#include "sonarsynth/formats/io/time_fields.hpp"

namespace sonarsynth::xtf {

FileSummary summarize(Reader& reader) {
  FileSummary s;
  s.name = reader.name();
  s.file_size = reader.file_size();
  s.header = reader.file_header();
  s.chan_info = reader.chan_info();
  Packet p;
  while (reader.next(p)) {
    ++s.packet_counts[p.header_type];
    switch (p.kind) {
      case PacketKind::kPing: {
        const PingRecord& ping = p.ping;
        const XtfPingHeader& h = ping.header;
        ++s.pings;
        if (ping.time_valid) {
          ++s.pings_with_valid_time;
          if (!s.first_time) s.first_time = ping.sonar.time_utc;
          s.last_time = ping.sonar.time_utc;
        }
        if (ping.nav_valid) {
          ++s.pings_with_valid_nav;
          s.sensor_x.add(h.SensorXcoordinate);
          s.sensor_y.add(h.SensorYcoordinate);
        }
        s.heading_deg.add(h.SensorHeading);
        s.pitch_deg.add(h.SensorPitch);
        s.roll_deg.add(h.SensorRoll);
        s.heave_m.add(h.Heave);
        s.altitude_m.add(h.SensorPrimaryAltitude);
        if (!(std::isfinite(h.SensorPrimaryAltitude) && h.SensorPrimaryAltitude > 0.0f)) {
          ++s.pings_without_altitude;
        }
        s.depth_m.add(h.SensorDepth);
        s.sound_velocity.add(h.SoundVelocity);
        for (std::size_t i = 0; i < ping.channel_count; ++i) {
          const ChannelData& ch = ping.channels[i];
          ChannelSummary& cs = s.channels[ch.header.ChannelNumber];
          ++cs.pings;
          cs.type_of_channel = ch.type_of_channel;
          cs.samples.add(static_cast<double>(ch.samples.size()));
          cs.slant_range_m.add(ch.header.SlantRange);
        }
        break;
      }
      case PacketKind::kAttitude:
        s.attitude_heading_deg.add(p.attitude.Heading);
        s.attitude_pitch_deg.add(p.attitude.Pitch);
        s.attitude_roll_deg.add(p.attitude.Roll);
        break;
      case PacketKind::kNavigation:
        if (p.navigation.RawXcoordinate != 0.0 && p.navigation.RawYcoordinate != 0.0) {
          ++s.navigation_packets_valid;
        }
        break;
      case PacketKind::kNotes:
      case PacketKind::kOther:
        break;
    }
  }
  s.anomaly_counts = reader.anomaly_counts();
  s.anomalies = reader.anomalies();
  return s;
}

FileSummary summarize_file(const std::filesystem::path& path, ReaderOptions options) {
  Reader reader(path, options);
  return summarize(reader);
}

std::string iso8601(UtcTime t) {
  const calendar::TimeFields f = calendar::fields_from_time(t);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%04d-%02u-%02uT%02u:%02u:%02u.%06uZ", f.year, f.month, f.day,
                f.hour, f.minute, f.second, static_cast<unsigned>(f.microsecond));
  return buf;
}

}  // namespace sonarsynth::xtf
