// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sonarsynth/formats/io/sonar_ping.hpp"
#include "sonarsynth/formats/rosbag/writer.hpp"
#include "sonarsynth/rendered_ping.hpp"
#include "sonarsynth/sonar.hpp"

/// The ROS 1 serialization of the messages of a sonarsynth bag, one message body each (what a
/// bag's message data record holds and what a ROS 1 publisher sends: docs/rosbag.md). The bag
/// writer and the live node (ros/, docs/robotics.md) both go through these, so the two write
/// every message the same way. Each appends to `out`.
namespace sonarsynth::rosbag {

/// `t` as ROS 1 time, nanoseconds since 1970. Throws InputError "<who>.time_utc = ..." outside
/// 1970-01-01 <= t < 2106-02-07.
std::uint64_t ros_time_ns(UtcTime t, const char* who);

/// marine_acoustic_msgs/RawSonarImage of one side of `ping` (seq = ping_number, frame
/// kPortFrame or kStarboardFrame), stamped `time_ns`; the samples quantised as
/// `options.sample_format` (clamped samples counted in `clipped`). The side must hold >= 1 sample
/// and ping.slant_range_m, ping.sound_speed_m_s be > 0 (Writer::write_ping checks).
void append_raw_sonar_image(std::vector<std::uint8_t>& out, const SonarPing& ping, bool starboard,
                            std::uint64_t time_ns, const WriterOptions& options,
                            std::uint64_t& clipped);
/// sonarsynth_msgs/SideScanTruth of one side's truth (seq = ping_number, frame kPortFrame or
/// kStarboardFrame), stamped `time_ns`: the sample count, then per sample the SampleClass code,
/// the label, the grazing angle (rad) and the ground range (m). The four truth vectors of `side`
/// must have one length (Writer::write_truth checks).
void append_side_scan_truth(std::vector<std::uint8_t>& out, const SonarPing& ping, bool starboard,
                            std::uint64_t time_ns, const SideOutput& side);
/// Why the sides' truth cannot become SideScanTruth messages ("<field> = <value>. Violated
/// constraint: ..."), or nullopt: each side was rendered with truth and its four truth vectors
/// have one length. Both bag writers' write_truth (ROS 1 and MCAP) check with it.
std::optional<std::string> truth_violation(const SideOutput& port, const SideOutput& starboard);
/// sensor_msgs/NavSatFix of the ping's sensor position (frame kVehicleFrame).
void append_nav_sat_fix(std::vector<std::uint8_t>& out, const SonarPing& ping,
                        std::uint64_t time_ns);
/// sensor_msgs/Imu of the attitude (frame kVehicleFrame; docs/rosbag.md for the angles).
void append_imu(std::vector<std::uint8_t>& out, std::uint32_t seq, std::uint64_t time_ns,
                double heading_true_rad, double pitch_rad, double roll_rad);
/// tf2_msgs/TFMessage of the two transforms kVehicleFrame -> kPortFrame, kStarboardFrame.
void append_tf_static(std::vector<std::uint8_t>& out, std::uint64_t time_ns, double tilt_rad);

/// The writer options of a simulation's bag: sample format, frequency, beam widths and tilt of
/// `sonar` (what `simulate` writes).
WriterOptions simulation_writer_options(const SonarConfig& sonar, const std::string& sample_format);

}  // namespace sonarsynth::rosbag
