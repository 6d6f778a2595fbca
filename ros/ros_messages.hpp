// SPDX-License-Identifier: MIT
// The generated ROS 1 messages the node uses, instantiated for C++20: their headers name
// ContainerAllocator::rebind<T>::other, which std::allocator lost in C++20, so the messages are
// instantiated with an allocator that still has it (std::allocator underneath; the string and
// array fields are std::basic_string / std::vector of it). Traits and serialization are those of
// the generated headers, which take any allocator.
#pragma once

#include <nav_msgs/Odometry.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Float64.h>

#include <memory>

namespace sonarsynth::ros_node {

template <class T>
struct RosAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = RosAllocator<U>;
  };
  RosAllocator() noexcept = default;
  template <class U>
  RosAllocator(const RosAllocator<U>&) noexcept {}
};

using Odometry = nav_msgs::Odometry_<RosAllocator<void>>;
using Image = sensor_msgs::Image_<RosAllocator<void>>;
using Float64 = std_msgs::Float64_<RosAllocator<void>>;

}  // namespace sonarsynth::ros_node
