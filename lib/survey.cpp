// SPDX-License-Identifier: MIT
#include "sonarsynth/survey.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "sonarsynth/error.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/keyed_random.hpp"

namespace sonarsynth {
namespace {

void require(bool ok, const std::string& what, double value, const char* constraint) {
  if (!ok) {
    throw InputError("vehicle: " + what + " = " + std::to_string(value) +
                     ". Violated constraint: " + constraint);
  }
}

// Sum of three sinusoids with hashed phases; |value| <= amplitude.
double disturbance(double amplitude, double period_s, double t_s, std::uint64_t seed,
                   std::uint64_t channel) {
  if (amplitude <= 0.0) return 0.0;
  static constexpr double kPeriods[3] = {1.0, 0.62, 1.43};
  static constexpr double kWeights[3] = {0.5, 0.3, 0.2};
  double v = 0.0;
  for (std::uint64_t k = 0; k < 3; ++k) {
    const double phase = 2.0 * kPi * uniform_from_bits(keyed_hash(seed, channel, 1000 + k));
    v += kWeights[k] * std::sin(2.0 * kPi * t_s / (period_s * kPeriods[k]) + phase);
  }
  return amplitude * v;
}

// Slow wander: five sinusoids of equal amplitude sqrt(2/5) rms (so the long-time RMS is `rms`)
// at angular frequencies w_k = c 2 pi / (period_s r_k), c chosen so that mean(w_k^2) =
// (2 pi / period_s)^2, with hashed phases.
double wander(double rms, double period_s, double t_s, std::uint64_t seed, std::uint64_t channel) {
  if (rms <= 0.0) return 0.0;
  static constexpr double kRatios[5] = {0.55, 0.75, 1.0, 1.35, 1.9};
  double mean_inv2 = 0.0;
  for (const double r : kRatios) mean_inv2 += 1.0 / (r * r) / 5.0;
  const double c = 1.0 / std::sqrt(mean_inv2);
  double v = 0.0;
  for (std::uint64_t k = 0; k < 5; ++k) {
    const double phase = 2.0 * kPi * uniform_from_bits(keyed_hash(seed, channel, 2000 + k));
    const double w = c * 2.0 * kPi / (period_s * kRatios[k]);
    v += std::sin(w * t_s + phase);
  }
  return rms * std::sqrt(2.0 / 5.0) * v;
}

// Off the grid: the height at the nearest grid point (the position clamped into the grid),
// or at the first valid node found in growing rings around it; 0 if there is none nearby.
// O(1) per call: never a scan of the grid.
double nearest_edge_height(const HeightGrid& seabed, const Eigen::Vector2d& xy) {
  const Eigen::Vector4d b = seabed.bounds();
  const double x = std::clamp(xy.x(), b[0], b[2]), y = std::clamp(xy.y(), b[1], b[3]);
  const double z = seabed.height_m(x, y);
  if (!std::isnan(z)) return z;
  const GridGeometry& g = seabed.geometry();
  const auto c0 = static_cast<long>(std::lround(g.col_of_x(x)));
  const auto r0 = static_cast<long>(std::lround(g.row_of_y(y)));
  for (long ring = 1; ring <= 16; ++ring) {
    for (long dr = -ring; dr <= ring; ++dr) {
      for (long dc = -ring; dc <= ring; ++dc) {
        if (std::max(std::abs(dr), std::abs(dc)) != ring) continue;
        const long r = r0 + dr, c = c0 + dc;
        if (r < 0 || c < 0 || r >= static_cast<long>(g.rows) || c >= static_cast<long>(g.cols))
          continue;
        const float v = seabed.node(static_cast<std::size_t>(c), static_cast<std::size_t>(r));
        if (v == v) return v;
      }
    }
  }
  return 0.0;
}

}  // namespace

void VehicleConfig::validate() const {
  require(speed_m_s > 0.0 && std::isfinite(speed_m_s), "speed_m_s", speed_m_s, "speed_m_s > 0");
  require(altitude_m > 0.0 && std::isfinite(altitude_m), "altitude_m", altitude_m,
          "altitude_m > 0");
  require(depth_m >= 0.0 && std::isfinite(depth_m), "depth_m", depth_m, "depth_m >= 0");
  require(layback_m >= 0.0 && std::isfinite(layback_m), "layback_m", layback_m, "layback_m >= 0");
  require(turn_radius_m >= 0.0, "turn_radius_m", turn_radius_m, "turn_radius_m >= 0");
  require(altitude_time_constant_s >= 0.0 && std::isfinite(altitude_time_constant_s),
          "altitude_time_constant_s", altitude_time_constant_s, "altitude_time_constant_s >= 0");
  require(disturbance.altitude_wander_m >= 0.0 && std::isfinite(disturbance.altitude_wander_m),
          "disturbance.altitude_m", disturbance.altitude_wander_m, "altitude_m >= 0");
  require(disturbance.heading_wander_rad >= 0.0 && disturbance.heading_wander_rad <= kPi / 4,
          "disturbance.heading_wander", disturbance.heading_wander_rad, "heading wander <= 45 deg");
  require(disturbance.wander_period_s > 0.0 && std::isfinite(disturbance.wander_period_s),
          "disturbance.wander_period_s", disturbance.wander_period_s, "wander_period_s > 0");
  require(disturbance.period_s > 0.0, "disturbance.period_s", disturbance.period_s, "period_s > 0");
  for (double a : {disturbance.roll_amplitude_rad, disturbance.pitch_amplitude_rad,
                   disturbance.yaw_amplitude_rad, disturbance.heave_amplitude_m}) {
    require(a >= 0.0 && std::isfinite(a), "disturbance amplitude", a, "amplitude >= 0");
  }
  require(disturbance.roll_amplitude_rad < kPi / 2, "disturbance.roll",
          disturbance.roll_amplitude_rad, "roll amplitude < 90 deg");
  require(disturbance.pitch_amplitude_rad < kPi / 2, "disturbance.pitch",
          disturbance.pitch_amplitude_rad, "pitch amplitude < 90 deg");
  if (!lever_arm_m.allFinite()) throw InputError("vehicle: lever_arm_m is not finite");
}

double SurveyLine::length_m() const {
  double len = 0.0;
  for (std::size_t i = 1; i < waypoints_xy_m.size(); ++i) {
    len += (waypoints_xy_m[i] - waypoints_xy_m[i - 1]).norm();
  }
  return len;
}

Survey::Survey(std::vector<SurveyLine> lines, VehicleConfig vehicle, double ping_period_s,
               UtcTime start_time, std::uint64_t seed)
    : lines_(std::move(lines)),
      vehicle_(vehicle),
      ping_period_s_(ping_period_s),
      start_time_(start_time),
      seed_(seed) {
  vehicle_.validate();
  if (!(ping_period_s > 0.0) || !std::isfinite(ping_period_s)) {
    throw InputError("survey: ping_period_s = " + std::to_string(ping_period_s) +
                     ". Violated constraint: ping_period_s > 0");
  }
  if (lines_.empty()) throw InputError("survey: no survey lines");
  first_ping_.push_back(0);
  double t = 0.0;
  for (std::size_t i = 0; i < lines_.size(); ++i) {
    const SurveyLine& l = lines_[i];
    if (l.waypoints_xy_m.size() < 2) {
      throw InputError("survey: line '" + l.name + "' has " +
                       std::to_string(l.waypoints_xy_m.size()) +
                       " waypoints. Violated constraint: >= 2 waypoints");
    }
    for (std::size_t k = 0; k < l.waypoints_xy_m.size(); ++k) {
      const Eigen::Vector2d& w = l.waypoints_xy_m[k];
      if (!w.allFinite()) {
        throw InputError("survey: line '" + l.name + "' waypoint " + std::to_string(k) + " = (" +
                         std::to_string(w.x()) + ", " + std::to_string(w.y()) +
                         ") m. Violated constraint: finite x and y (waypoints counted from 0)");
      }
    }
    std::vector<double> cum{0.0};
    for (std::size_t k = 1; k < l.waypoints_xy_m.size(); ++k) {
      const double d = (l.waypoints_xy_m[k] - l.waypoints_xy_m[k - 1]).norm();
      if (!(d > 0.0)) {
        throw InputError("survey: line '" + l.name + "' repeats waypoint " + std::to_string(k) +
                         ". Violated constraint: consecutive waypoints differ");
      }
      cum.push_back(cum.back() + d);
    }
    const double spacing = vehicle_.speed_m_s * ping_period_s_;
    const auto n = static_cast<std::size_t>(std::floor(cum.back() / spacing)) + 1;
    cumulative_m_.push_back(std::move(cum));
    ping_counts_.push_back(n);
    first_ping_.push_back(first_ping_.back() + n);
    line_start_time_s_.push_back(t);
    t += static_cast<double>(n) * ping_period_s_;
    if (i + 1 < lines_.size()) {
      const double gap = (lines_[i + 1].waypoints_xy_m.front() - l.waypoints_xy_m.back()).norm();
      t += vehicle_.turn_time_s >= 0.0 ? vehicle_.turn_time_s
                                       : (gap + kPi * vehicle_.turn_radius_m) / vehicle_.speed_m_s;
    }
  }
}

void Survey::along_line(std::size_t line, double s_m, Eigen::Vector2d& xy,
                        double& azimuth_rad) const {
  const auto& cum = cumulative_m_[line];
  const auto& wp = lines_[line].waypoints_xy_m;
  // Before the start (layback at the first ping) the line is extended backwards straight.
  std::size_t k = 1;
  while (k + 1 < cum.size() && s_m > cum[k]) ++k;
  const Eigen::Vector2d a = wp[k - 1], b = wp[k];
  const Eigen::Vector2d u = (b - a) / (cum[k] - cum[k - 1]);
  xy = a + (s_m - cum[k - 1]) * u;
  azimuth_rad = std::atan2(u.x(), u.y());
}

double Survey::followed_height_m(std::size_t line, double s_m, const HeightGrid& seabed) const {
  Eigen::Vector2d xy;
  double az = 0.0;
  along_line(line, s_m, xy, az);
  const double tau = vehicle_.altitude_time_constant_s;
  if (!(tau > 0.0)) return seabed.height_m(xy.x(), xy.y());
  // Trapezoid rule over u in [0, 8 tau] (the weight beyond is e^-8 = 3e-4 of the total) at
  // steps of tau / 32 and at most half a grid cell of track, at most 4096 steps; holes and
  // off-grid points leave their weight out (the mean is over the valid heights).
  const GridGeometry& g = seabed.geometry();
  const double cell = std::min(std::abs(g.dx_m), std::abs(g.dy_m));
  const double v = vehicle_.speed_m_s;
  const double span = 8.0 * tau;
  const double du = std::max({std::min(tau / 32.0, 0.5 * cell / v), span / 4096.0});
  const auto steps = static_cast<int>(std::ceil(span / du));
  double sum = 0.0, weight = 0.0;
  for (int i = 0; i <= steps; ++i) {
    const double u = span * static_cast<double>(i) / static_cast<double>(steps);
    along_line(line, s_m - v * u, xy, az);
    const double h = seabed.height_m(xy.x(), xy.y());
    if (std::isnan(h)) continue;
    const double w = std::exp(-u / tau) * (i == 0 || i == steps ? 0.5 : 1.0);
    sum += w * h;
    weight += w;
  }
  return weight > 0.0 ? sum / weight : std::numeric_limits<double>::quiet_NaN();
}

PingPose Survey::pose(std::uint64_t index, const HeightGrid& seabed) const {
  if (index >= total_pings()) throw InputError("survey: ping index out of range");
  const auto it = std::upper_bound(first_ping_.begin(), first_ping_.end(), index);
  const std::size_t line = static_cast<std::size_t>(it - first_ping_.begin()) - 1;
  PingPose p;
  p.line = line;
  p.ping_in_line = static_cast<std::size_t>(index - first_ping_[line]);
  p.ping_index = index;
  const double t_s =
      line_start_time_s_[line] + static_cast<double>(p.ping_in_line) * ping_period_s_;
  p.time_utc = start_time_ + std::chrono::microseconds(std::llround(t_s * 1e6));
  p.speed_m_s = vehicle_.speed_m_s;

  const double s = static_cast<double>(p.ping_in_line) * vehicle_.speed_m_s * ping_period_s_;
  double az_ref = 0.0, az_fish = 0.0;
  along_line(line, s, p.reference_xy_m, az_ref);
  Eigen::Vector2d fish_xy;
  along_line(line, s - vehicle_.layback_m, fish_xy, az_fish);
  p.along_track_m = s - vehicle_.layback_m;

  const Disturbance& d = vehicle_.disturbance;
  p.heading_rad = az_fish + disturbance(d.yaw_amplitude_rad, d.period_s, t_s, seed_, 1);
  p.pitch_rad = disturbance(d.pitch_amplitude_rad, d.period_s, t_s, seed_, 2);
  p.roll_rad = disturbance(d.roll_amplitude_rad, d.period_s, t_s, seed_, 3);
  p.heave_m = disturbance(d.heave_amplitude_m, d.period_s, t_s, seed_, 4);
  p.heading_rad += wander(d.heading_wander_rad, d.wander_period_s, t_s, seed_, 5);
  const double z_wander = wander(d.altitude_wander_m, d.wander_period_s, t_s, seed_, 6);

  // Lever arm: body (forward, starboard) rotated by the heading; down subtracts from z.
  const Eigen::Vector2d fwd(std::sin(p.heading_rad), std::cos(p.heading_rad));
  const Eigen::Vector2d stbd(fwd.y(), -fwd.x());
  p.sensor_xy_m = fish_xy + vehicle_.lever_arm_m.x() * fwd + vehicle_.lever_arm_m.y() * stbd;

  const double seabed_z = seabed.height_m(p.sensor_xy_m.x(), p.sensor_xy_m.y());
  if (vehicle_.depth_mode == VehicleConfig::DepthMode::kAltitude) {
    // Terrain following; over a hole or off the grid, keep the altitude over the seabed's
    // nearest valid height behind the sensor (searched along the track, deterministic).
    double z = vehicle_.altitude_time_constant_s > 0.0
                   ? followed_height_m(line, p.along_track_m, seabed)
                   : seabed_z;
    for (int k = 1; std::isnan(z) && k <= 200; ++k) {
      const Eigen::Vector2d q = p.sensor_xy_m - 0.5 * k * fwd;
      z = seabed.height_m(q.x(), q.y());
    }
    if (std::isnan(z)) z = nearest_edge_height(seabed, p.sensor_xy_m);
    p.sensor_z_m = z + vehicle_.altitude_m + z_wander + p.heave_m - vehicle_.lever_arm_m.z();
  } else {
    p.sensor_z_m = -vehicle_.depth_m + z_wander + p.heave_m - vehicle_.lever_arm_m.z();
  }
  p.altitude_m = p.sensor_z_m - seabed_z;
  return p;
}

}  // namespace sonarsynth

namespace sonarsynth {

PingPose sensor_pose(const Eigen::Vector3d& position_m, double heading_rad, double pitch_rad,
                     double roll_rad, const HeightGrid& seabed,
                     std::optional<std::uint64_t> noise_key) {
  PingPose p;
  p.ping_index = noise_key;
  p.sensor_xy_m = position_m.head<2>();
  p.sensor_z_m = position_m.z();
  p.reference_xy_m = p.sensor_xy_m;
  p.heading_rad = heading_rad;
  p.pitch_rad = pitch_rad;
  p.roll_rad = roll_rad;
  p.altitude_m = position_m.z() - seabed.height_m(position_m.x(), position_m.y());  // NaN off grid
  return p;
}

}  // namespace sonarsynth

namespace sonarsynth {

namespace {

// A number in a message: up to 10 significant digits ("nan", "inf", "-1020", "1.5").
std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

}  // namespace

std::string pose_error(const PingPose& pose, const HeightGrid& seabed,
                       const PoseFieldNames& names) {
  const auto bad = [](const char* field, double v, const std::string& constraint) {
    return std::string(field) + " = " + number_text(v) + ". Violated constraint: " + constraint;
  };
  const std::pair<const char*, double> finite[] = {{names.x, pose.sensor_xy_m.x()},
                                                   {names.y, pose.sensor_xy_m.y()},
                                                   {names.z, pose.sensor_z_m},
                                                   {names.heading, pose.heading_rad}};
  for (const auto& [field, v] : finite) {
    if (!std::isfinite(v)) return bad(field, v, "a finite number");
  }
  const double max_rad = rad_from_deg(kMaxAttitudeDeg);
  const std::string attitude = " <= " + number_text(max_rad) + " rad (" +
                               number_text(kMaxAttitudeDeg) +
                               " deg, the bound of the scene "
                               "file's survey.disturbance)";
  if (!(std::abs(pose.pitch_rad) <= max_rad)) {
    return bad(names.pitch, pose.pitch_rad, std::string("|") + names.pitch + "|" + attitude);
  }
  if (!(std::abs(pose.roll_rad) <= max_rad)) {
    return bad(names.roll, pose.roll_rad, std::string("|") + names.roll + "|" + attitude);
  }
  if (std::isinf(pose.altitude_m)) {
    return bad("altitude_m", pose.altitude_m, "a finite number, or NaN (unknown)");
  }
  if (std::isinf(pose.along_track_m)) {
    return bad("along_track_m", pose.along_track_m, "a finite number, or NaN (unknown)");
  }
  if (!(std::isfinite(pose.speed_m_s) && pose.speed_m_s >= 0.0)) {
    return bad("speed_m_s", pose.speed_m_s, "speed_m_s >= 0 (finite)");
  }
  const double x = pose.sensor_xy_m.x(), y = pose.sensor_xy_m.y();
  const double h = seabed.height_m(x, y);
  if (std::isnan(h)) return {};  // off the grid or over a hole: no seabed to check against
  const std::string at = " at (" + std::string(names.x) + ", " + names.y + ") = (" +
                         number_text(x) + ", " + number_text(y) + ")";
  if (!(pose.sensor_z_m - h > 0.0)) {
    return bad(names.z, pose.sensor_z_m,
               std::string(names.z) + " > " + number_text(h) + " m, the seabed height" + at +
                   " (the sensor above the seabed: altitude " + number_text(pose.sensor_z_m - h) +
                   " m)");
  }
  if (pose.sensor_z_m > 0.0) {
    return bad(names.z, pose.sensor_z_m,
               std::string(names.z) + " <= 0 (the sensor below the sea surface, height 0; seabed " +
                   number_text(h) + " m" + at + ")");
  }
  return {};
}

void check_pose(const PingPose& pose, const HeightGrid& seabed, const std::string& who,
                const PoseFieldNames& names) {
  const std::string e = pose_error(pose, seabed, names);
  if (!e.empty()) throw InputError(who + ": " + e);
}

}  // namespace sonarsynth
