// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <chrono>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "sonarsynth/height_grid.hpp"

namespace sonarsynth {

/// UTC time with microsecond resolution.
using UtcTime = std::chrono::sys_time<std::chrono::microseconds>;

/// Smooth, seeded attitude and heave disturbances: each channel is a sum of three sinusoids of
/// periods period_s x {1, 0.62, 1.43} with hashed phases, scaled to the given amplitude (peak of
/// the sum <= amplitude). Zero amplitudes cost nothing.
struct Disturbance {
  double roll_amplitude_rad = 0.0;   ///< >= 0
  double pitch_amplitude_rad = 0.0;  ///< >= 0
  double yaw_amplitude_rad = 0.0;    ///< >= 0
  double heave_amplitude_m = 0.0;    ///< >= 0
  double period_s = 8.0;             ///< dominant period, seconds, > 0
  /// Slow wander of the altitude (or the depth, DepthMode::kDepth), RMS metres, >= 0: an
  /// altitude controller's hold error and the pilot's changes. Added to the height of the
  /// sensor like the heave. Each wander channel is a sum of five sinusoids of equal amplitude
  /// and hashed phases whose angular frequencies are spread over a factor 3.5 around
  /// 2 pi / wander_period_s with mean square exactly (2 pi / wander_period_s)^2, so over a long
  /// line its RMS is the value given and RMS(d/dt) / RMS = 2 pi / wander_period_s.
  double altitude_wander_m = 0.0;
  /// Slow wander of the heading about the track (crab angle), RMS radians, [0, pi/4].
  double heading_wander_rad = 0.0;
  double wander_period_s = 120.0;  ///< rms-frequency period of the wanders, seconds, > 0
  bool any() const {
    return roll_amplitude_rad > 0 || pitch_amplitude_rad > 0 || yaw_amplitude_rad > 0 ||
           heave_amplitude_m > 0 || altitude_wander_m > 0 || heading_wander_rad > 0;
  }
};

/// How the vehicle moves. The survey lines are followed by the navigation reference point (the
/// ship for a towed fish, the AUV itself otherwise); the transducers sit `layback_m` behind it
/// along the track and then at `lever_arm_m` in the body frame.
struct VehicleConfig {
  enum class DepthMode {
    kAltitude,  ///< terrain following: sensor at altitude_m above the seabed under it
    kDepth,     ///< constant depth: sensor at z = -depth_m (bathymetry datum = sea surface)
  };
  double speed_m_s = 2.0;  ///< speed along the lines, m/s, > 0
  DepthMode depth_mode = DepthMode::kAltitude;
  double altitude_m = 10.0;  ///< kAltitude: height above the seabed, metres, > 0
  /// kAltitude: time constant of the altitude controller, seconds, >= 0. The sensor follows the
  /// seabed under its track through a first-order lag, z(t) = altitude_m + integral over u >= 0
  /// of exp(-u / tau) / tau h(t - u) du (h: seabed height under the track at time t - u, the
  /// line extended straight before its start), so it lags over slopes and rounds steps off with
  /// 1 - exp(-t / tau). 0 = exact terrain following.
  double altitude_time_constant_s = 0.0;
  double depth_m = 10.0;   ///< kDepth: depth below the surface, metres, >= 0
  double layback_m = 0.0;  ///< towfish distance behind the navigation reference, metres, >= 0
  /// Transducer offset from the towpoint/reference in the body frame: (forward, starboard,
  /// down), metres.
  Eigen::Vector3d lever_arm_m = Eigen::Vector3d::Zero();
  Disturbance disturbance;
  /// Time between two lines (the turn), seconds; < 0 = computed as (straight distance between
  /// the line end and the next start + pi * turn_radius_m) / speed.
  double turn_time_s = -1.0;
  double turn_radius_m = 25.0;  ///< for the computed turn time, metres, >= 0

  void validate() const;
};

/// One survey line: a polyline of waypoints in the local frame, followed at constant speed.
struct SurveyLine {
  std::string name;
  std::vector<Eigen::Vector2d> waypoints_xy_m;  ///< >= 2 distinct points
  double length_m() const;
};

/// The pose of the transducers at one ping.
///
/// Frames (how the renderer uses the pose: docs/physics.md §2.1): positions are in the scene's
/// local frame: x along grid east, y along grid north, z up, metres, z on the bathymetry's
/// vertical datum. The attitude is the body frame (x forward, y starboard, z down) rotated from
/// the local level frame by heading about the vertical, then pitch about the rotated starboard
/// axis, then roll about the forward axis (the order of aircraft and XTF attitude).
///
/// Noise key: the noise of a ping (speckle of non-seabed samples, thermal noise, the paper's
/// multiplicative term) is a pure function of (SimulationConfig::seed, ping_index). A Survey sets
/// it to the global ping number. Left unset, Simulator::render_ping assigns a fresh key from its
/// own counter (2^63 + n for the n-th unkeyed ping), so two unkeyed pings never share noise; set
/// it for noise that is reproducible independently of the call order.
struct PingPose {
  std::size_t line = 0;  ///< index of the survey line
  std::size_t ping_in_line = 0;
  /// Global ping number (0-based, over all lines) and noise key; see above. Values >= 2^63 are
  /// those the Simulator assigns itself.
  std::optional<std::uint64_t> ping_index;
  UtcTime time_utc{};
  Eigen::Vector2d sensor_xy_m = Eigen::Vector2d::Zero();  ///< transducers, local frame
  double sensor_z_m = 0.0;  ///< transducers' height, local frame, same datum as the bathymetry
  Eigen::Vector2d reference_xy_m = Eigen::Vector2d::Zero();  ///< navigation reference (ship)
  double heading_rad = 0.0;  ///< grid azimuth of the body x axis, clockwise from grid north
  double pitch_rad = 0.0;    ///< + nose up, (-pi/2, pi/2)
  double roll_rad = 0.0;     ///< + starboard down, [-pi, pi]
  double heave_m = 0.0;      ///< + up (recorded; already included in sensor_z_m)
  double altitude_m = 0.0;   ///< transducers above the seabed under them (NaN if unknown)
  double speed_m_s = 0.0;
  /// Distance of the sensor along its survey line, metres (Survey sets it; NaN = unknown). It
  /// anchors the along-track speckle lattice (NoiseConfig::along_track_correlation), so pings of
  /// one line share scatterers however the heading jitters; when NaN, the position projected on
  /// the heading is used (right for a straight track at a constant heading).
  double along_track_m = std::numeric_limits<double>::quiet_NaN();
};

/// A full sensor pose for one ping rendered outside a survey: `position_m` (local frame, z on
/// the bathymetry datum) and attitude as documented on PingPose; the altitude is taken from
/// `seabed` under the sensor (NaN off the grid), the navigation reference is the sensor itself.
/// `noise_key` as PingPose::ping_index (nullopt: the Simulator assigns one).
PingPose sensor_pose(const Eigen::Vector3d& position_m, double heading_rad, double pitch_rad,
                     double roll_rad, const HeightGrid& seabed,
                     std::optional<std::uint64_t> noise_key = std::nullopt);

/// The largest pitch and roll of a pose, degrees: the bound of a scene file's
/// survey.disturbance.pitch_deg and roll_deg (whose sum of sinusoids peaks at most there).
inline constexpr double kMaxAttitudeDeg = 89.0;

/// The names check_pose() gives the checked fields in its messages (by default those of PingPose
/// and of the Python module's POSE_DTYPE).
struct PoseFieldNames {
  const char* x = "sensor_x_m";
  const char* y = "sensor_y_m";
  const char* z = "sensor_z_m";
  const char* heading = "heading_rad";
  const char* pitch = "pitch_rad";
  const char* roll = "roll_rad";
};

/// What is wrong with a pose given to a renderer from outside a survey, or "" if nothing. The
/// rules (docs/python.md "Pose checks"): position, heading, pitch and roll finite; |pitch| and
/// |roll| <= kMaxAttitudeDeg; altitude_m and along_track_m finite or NaN (unknown), speed_m_s
/// finite and >= 0. Where `seabed` has a height h at the sensor's (x, y), the sensor must lie
/// above it and not above the sea surface, 0 < sensor_z_m - h and sensor_z_m <= 0, the rule of a
/// scene file's survey lines; off the grid or over a hole there is no seabed to check against
/// (a survey renders such pings without seabed). The message names the field, the value and the
/// allowed range: "sensor_z_m = -1020 ... Violated constraint: ...".
std::string pose_error(const PingPose& pose, const HeightGrid& seabed,
                       const PoseFieldNames& names = {});

/// Throws InputError("<who>: <pose_error>") if pose_error() finds something.
void check_pose(const PingPose& pose, const HeightGrid& seabed, const std::string& who,
                const PoseFieldNames& names = {});

/// A survey: lines, the vehicle, the ping timing. Poses are a pure function of the ping index,
/// so pings can be rendered in any order or in parallel.
class Survey {
 public:
  /// ping_period_s > 0; start_time is the first ping of the first line.
  Survey(std::vector<SurveyLine> lines, VehicleConfig vehicle, double ping_period_s,
         UtcTime start_time, std::uint64_t seed);

  std::size_t line_count() const { return lines_.size(); }
  const SurveyLine& line(std::size_t i) const { return lines_.at(i); }
  std::size_t pings_in_line(std::size_t line) const { return ping_counts_.at(line); }
  std::uint64_t total_pings() const { return first_ping_.back(); }
  double ping_period_s() const { return ping_period_s_; }
  const VehicleConfig& vehicle() const { return vehicle_; }

  /// Pose of global ping `index` (0 <= index < total_pings()) over `seabed`.
  PingPose pose(std::uint64_t index, const HeightGrid& seabed) const;

 private:
  // The seabed height the altitude controller follows at distance s_m along the line (the
  // sensor's track, lever arm left out): the height itself, or with a time constant the
  // exponentially weighted mean of the heights behind (docs/physics.md §1.4 "Survey motion").
  double followed_height_m(std::size_t line, double s_m, const HeightGrid& seabed) const;
  // Position and grid azimuth at distance s along a line (clamped to the line).
  void along_line(std::size_t line, double s_m, Eigen::Vector2d& xy, double& azimuth_rad) const;

  std::vector<SurveyLine> lines_;
  VehicleConfig vehicle_;
  double ping_period_s_;
  UtcTime start_time_;
  std::uint64_t seed_;
  std::vector<std::size_t> ping_counts_;
  std::vector<std::uint64_t> first_ping_;  // global index of each line's first ping (+ total)
  std::vector<double> line_start_time_s_;  // seconds after start_time
  std::vector<std::vector<double>> cumulative_m_;  // per line: distance at each waypoint
};

}  // namespace sonarsynth
