// SPDX-License-Identifier: MIT
// The orientations of the ROS bags (formats/rosbag and formats/mcap): a ZYX rotation as a
// geometry_msgs/Quaternion and the float64 fields of its message written through either
// serialization (ROS 1 or CDR, each writer with an f64 of its own), docs/rosbag.md and
// docs/robotics.md.
#pragma once

#include <cmath>

namespace sonarsynth::rosbag {

/// A unit quaternion (x, y, z, w), as geometry_msgs/Quaternion orders it.
struct Quaternion {
  double x = 0.0, y = 0.0, z = 0.0, w = 1.0;
};

/// ZYX (yaw about z, then pitch about the new y, then roll about the new x) rotation as a
/// quaternion.
inline Quaternion quaternion_zyx(double yaw, double pitch, double roll) {
  const double cy = std::cos(yaw / 2), sy = std::sin(yaw / 2);
  const double cp = std::cos(pitch / 2), sp = std::sin(pitch / 2);
  const double cr = std::cos(roll / 2), sr = std::sin(roll / 2);
  return {sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy,
          cr * cp * cy + sr * sp * sy};
}

/// geometry_msgs/Quaternion: x, y, z, w as float64.
template <class Writer>
void put_quaternion(Writer& w, const Quaternion& q) {
  w.f64(q.x);
  w.f64(q.y);
  w.f64(q.z);
  w.f64(q.w);
}

/// A float64[9] covariance: element 0 `first` (-1: "no estimate"), the others 0.
template <class Writer>
void put_covariance(Writer& w, double first) {
  w.f64(first);
  for (int i = 1; i < 9; ++i) w.f64(0.0);
}

}  // namespace sonarsynth::rosbag
