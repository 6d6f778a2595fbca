// SPDX-License-Identifier: MIT
// The ROS-free part of the live node sonarsynth_ros (docs/robotics.md, "The live ROS 1 node"):
// odometry poses to renderer poses, the ping clock, the simulation with the node's parameters
// applied, the rolling waterfall image.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/colormap.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"
#include "sonarsynth/rendered_ping.hpp"
#include "sonarsynth/simulator.hpp"
#include "sonarsynth/survey.hpp"

namespace sonarsynth::ros_node {

/// A pose of the vehicle (base_link) in the odom frame at a time (docs/robotics.md, "Frames"):
/// odom is the scene's local frame, x grid east, y grid north, z up on the bathymetry's datum
/// (ENU, REP 103 / REP 105); base_link is x forward, y left, z up.
struct OdomSample {
  std::uint64_t stamp_ns = 0;  ///< header.stamp, nanoseconds
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< base_link in odom
  double speed_m_s = 0.0;                                           ///< |twist.twist.linear|
};

/// The renderer's attitude of a base_link orientation in odom: heading clockwise from grid north
/// (pi/2 - yaw), pitch + nose up (- the ROS pitch), roll + starboard down (the ROS roll), from
/// the Z-Y'-X'' (yaw, pitch, roll) angles of `q` (normalised first).
struct Attitude {
  double heading_rad = 0.0;
  double pitch_rad = 0.0;
  double roll_rad = 0.0;
};
Attitude attitude_of(const Eigen::Quaterniond& q);

/// The pose at `t_ns`, a.stamp_ns <= t_ns <= b.stamp_ns: position and speed linear in time,
/// orientation by slerp; exactly `a` at a.stamp_ns and `b` at b.stamp_ns.
OdomSample interpolate(const OdomSample& a, const OdomSample& b, std::uint64_t t_ns);

/// The renderer's pose of ping `ping_index` (its noise key, and ping_in_line of line 0) at `s`:
/// the sonar at base_link's origin (docs/robotics.md), altitude from `seabed`, time_utc the stamp
/// (microseconds, truncated).
PingPose ping_pose(const OdomSample& s, std::uint64_t ping_index, const HeightGrid& seabed);

/// One ping due: its index (0, 1, ...), time and the pose interpolated to it.
struct ScheduledPing {
  std::uint64_t index = 0;
  std::uint64_t time_ns = 0;
  OdomSample pose;
};

/// The ping clock: ping k at t0 + round(k period), t0 the first pose's stamp. A ping is due when
/// a pose at or after its time arrives; its pose is interpolated between that pose and the one
/// before. Pings in a gap between poses longer than `max_gap_s` are skipped (no interpolation
/// across a dropout), and counted.
class PingClock {
 public:
  /// period_s > 0, max_gap_s > 0; throws InputError naming the value otherwise.
  PingClock(double period_s, double max_gap_s);
  /// Takes the next pose and appends the pings now due to `due`. A pose not later than the
  /// previous one is refused (false; nothing changes).
  bool add(const OdomSample& s, std::vector<ScheduledPing>& due);
  std::uint64_t ping_time_ns(std::uint64_t index) const;
  std::uint64_t skipped() const { return skipped_; }
  std::uint64_t next_index() const { return next_; }

 private:
  double period_ns_;
  std::uint64_t max_gap_ns_;
  bool started_ = false;
  OdomSample last_;
  std::uint64_t t0_ns_ = 0, next_ = 0, skipped_ = 0;
};

/// Parameter values for the scene file's options (docs/robotics.md, "Parameters"): key path
/// ("sonar.range_m", "seed") -> YAML scalar text.
using OptionValues = std::vector<std::pair<std::string, std::string>>;

/// The key paths of the option table (formats/config/option_table.cpp), as the node reads them
/// from its private namespace: "sonar.range_m" -> "sonar/range_m", "seed" -> "seed".
std::vector<std::string> option_paths();

/// Loads the scene file at `path` as `sonarsynth simulate` does, with `values` written into its
/// YAML first (each path must be one of option_paths(); the file's own checks then name the key
/// and value) and `overrides` applied (the CLI's --seed, --range, --samples, --quality).
SimulationSetup load_setup(const std::string& path, const OptionValues& values,
                           const SimulationOverrides& overrides);

/// The Simulator of `setup` as `simulate` and the Python module build it: the setup's reference
/// altitude and, when the file has survey lines, their pilot poses. Moves the scene out.
std::shared_ptr<const Simulator> make_simulator(SimulationSetup& setup);

/// The latency statistics of the node's log line (docs/robotics.md, "Latency") in fixed memory: a
/// log-scale histogram of kBinsPerOctave bins per octave from kLowestS to kHighestS (about 7.7 KB,
/// whatever the number of pings), with the count, minimum and maximum kept exactly.
/// quantile(q) is the nearest-rank q-quantile (the ceil(q n)-th smallest value) to within a
/// relative error of kRelativeError (1.09 %): the bin holding that value is found exactly and
/// its geometric centre reported, clamped to [min, max]. Values below kLowestS (including 0)
/// are reported to within kLowestS absolute; values above kHighestS as the maximum.
class LatencyHistogram {
 public:
  static constexpr int kBinsPerOctave = 32;
  static constexpr int kOctaves = 30;
  static constexpr double kLowestS = 1e-6;
  static constexpr double kHighestS = kLowestS * double(1ull << kOctaves);  ///< ~1074 s
  /// 2^(1 / (2 kBinsPerOctave)) - 1: half a bin's width, as a ratio.
  static const double kRelativeError;

  /// Adds one latency, seconds (a negative or NaN value counts as 0).
  void add(double latency_s);
  /// The nearest-rank q-quantile, 0 < q <= 1 (0 when empty).
  double quantile(double q) const;
  std::uint64_t count() const { return count_; }
  double min() const { return count_ ? min_ : 0.0; }
  double max() const { return count_ ? max_ : 0.0; }
  void clear();

 private:
  static constexpr std::size_t kBins = std::size_t{kBinsPerOctave} * kOctaves + 2;
  std::array<std::uint64_t, kBins> counts_{};  ///< [0] below kLowestS, [kBins-1] above kHighestS
  std::uint64_t count_ = 0;
  double min_ = 0.0, max_ = 0.0;
};

/// The rolling waterfall (docs/robotics.md): `rows` rows of 2 x samples pixels, RGB 8-bit, the
/// newest ping at the top, port far -> near on the left then starboard near -> far; a sample s
/// is shown as colormap(s / full_scale) (the founding paper's linear grey level and map).
class Waterfall {
 public:
  Waterfall(std::size_t rows, std::size_t samples, Colormap map, double full_scale);
  void add(const RenderedPing& ping);
  /// The image into `rgb` (rows x width x 3 bytes), newest row first (rows not yet filled
  /// black).
  void image(std::uint8_t* rgb) const;
  std::size_t rows() const { return rows_; }
  std::size_t width() const { return 2 * samples_; }

 private:
  std::size_t rows_, samples_;
  Colormap map_;
  double full_scale_;
  std::vector<std::uint8_t> ring_;  ///< rows_ rows, row `head_` the newest
  std::size_t head_ = 0, filled_ = 0;
};

}  // namespace sonarsynth::ros_node
