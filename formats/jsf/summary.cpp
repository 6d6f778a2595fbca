// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/jsf/summary.hpp"

#include <cmath>

#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::jsf {

FileSummary summarize(Reader& reader) {
  FileSummary s;
  s.name = reader.name();
  s.file_size = reader.file_size();
  Ping p;
  while (reader.next_ping(p)) {
    ++s.pings;
    const SonarPing& q = p.sonar;
    if (p.time_valid) {
      ++s.pings_with_valid_time;
      if (!s.first_time) s.first_time = q.time_utc;
      s.last_time = q.time_utc;
    }
    if (p.nav_valid) {
      ++s.pings_with_valid_nav;
      s.longitude_deg.add(deg_from_rad(q.sensor_position.lon_rad));
      s.latitude_deg.add(deg_from_rad(q.sensor_position.lat_rad));
    }
    s.samples.add(static_cast<double>(std::max(q.port.size(), q.starboard.size())));
    s.slant_range_m.add(q.slant_range_m);
    s.sample_interval_ns.add(p.header.sample_interval_ns);
    s.weighting_factor.add(p.header.weighting_factor);
    s.heading_deg.add(deg_from_rad(q.heading_true_rad));
    s.pitch_deg.add(deg_from_rad(q.pitch_rad));
    s.roll_deg.add(deg_from_rad(q.roll_rad));
    s.heave_m.add(q.heave_m);
    s.altitude_m.add(q.altitude_m);
    if (!(q.altitude_m > 0.0)) ++s.pings_without_altitude;
    s.depth_m.add(q.depth_m);
    s.sound_speed_m_s.add(q.sound_speed_m_s);
  }
  s.message_counts = reader.message_counts();
  s.sonar_counts = reader.sonar_counts();
  s.system_information = reader.system_information();
  s.ping_subsystem = reader.subsystem();
  s.anomaly_counts = reader.anomaly_counts();
  s.anomalies = reader.anomalies();
  return s;
}

FileSummary summarize_file(const std::filesystem::path& path, ReaderOptions options) {
  Reader reader(path, options);
  return summarize(reader);
}

}  // namespace sonarsynth::jsf
