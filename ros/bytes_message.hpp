// SPDX-License-Identifier: MIT
// A ROS 1 message held as its serialized bytes, for roscpp: the messages of a sonarsynth bag
// (marine_acoustic_msgs/RawSonarImage, sensor_msgs/NavSatFix, sensor_msgs/Imu,
// tf2_msgs/TFMessage) are written by the bag codec's functions (formats/rosbag, message_bytes.hpp)
// and published as they are; their type, MD5 sum and definition are the codec's too
// (docs/rosbag.md, "Message definitions"), so a subscriber or `rosbag record` sees exactly what a
// sonarsynth bag holds.
#pragma once

#include <ros/message_traits.h>
#include <ros/serialization.h>

#include <boost/shared_ptr.hpp>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "sonarsynth/formats/rosbag/messages.hpp"

namespace sonarsynth::ros_node {

/// One message of the ROS 1 type `Type::kName`, as bytes (the message's serialization).
template <class Type>
struct BytesMessage {
  using ConstPtr = boost::shared_ptr<const BytesMessage>;
  std::vector<std::uint8_t> bytes;
};

struct RawSonarImageType {
  static constexpr const char* kName = "marine_acoustic_msgs/RawSonarImage";
};
struct NavSatFixType {
  static constexpr const char* kName = "sensor_msgs/NavSatFix";
};
struct ImuType {
  static constexpr const char* kName = "sensor_msgs/Imu";
};
struct TfMessageType {
  static constexpr const char* kName = "tf2_msgs/TFMessage";
};

using RawSonarImageBytes = BytesMessage<RawSonarImageType>;
using NavSatFixBytes = BytesMessage<NavSatFixType>;
using ImuBytes = BytesMessage<ImuType>;
using TfMessageBytes = BytesMessage<TfMessageType>;

}  // namespace sonarsynth::ros_node

namespace ros::message_traits {

template <class T>
struct IsMessage<sonarsynth::ros_node::BytesMessage<T>> : TrueType {};

template <class T>
struct MD5Sum<sonarsynth::ros_node::BytesMessage<T>> {
  static const char* value() {
    static const std::string md5 = sonarsynth::rosbag::message_md5(T::kName);
    return md5.c_str();
  }
  static const char* value(const sonarsynth::ros_node::BytesMessage<T>&) { return value(); }
};

template <class T>
struct DataType<sonarsynth::ros_node::BytesMessage<T>> {
  static const char* value() { return T::kName; }
  static const char* value(const sonarsynth::ros_node::BytesMessage<T>&) { return value(); }
};

template <class T>
struct Definition<sonarsynth::ros_node::BytesMessage<T>> {
  static const char* value() {
    static const std::string text = sonarsynth::rosbag::message_definition(T::kName);
    return text.c_str();
  }
  static const char* value(const sonarsynth::ros_node::BytesMessage<T>&) { return value(); }
};

}  // namespace ros::message_traits

namespace ros::serialization {

template <class T>
struct Serializer<sonarsynth::ros_node::BytesMessage<T>> {
  template <typename Stream>
  static void write(Stream& stream, const sonarsynth::ros_node::BytesMessage<T>& m) {
    if (!m.bytes.empty()) {
      std::memcpy(stream.advance(static_cast<std::uint32_t>(m.bytes.size())), m.bytes.data(),
                  m.bytes.size());
    }
  }
  /// The whole remaining stream is the message.
  template <typename Stream>
  static void read(Stream& stream, sonarsynth::ros_node::BytesMessage<T>& m) {
    const std::uint32_t n = stream.getLength();
    const std::uint8_t* p = stream.advance(n);
    m.bytes.assign(p, p + n);
  }
  static std::uint32_t serializedLength(const sonarsynth::ros_node::BytesMessage<T>& m) {
    return static_cast<std::uint32_t>(m.bytes.size());
  }
};

}  // namespace ros::serialization
