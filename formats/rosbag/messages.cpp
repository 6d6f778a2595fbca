// SPDX-License-Identifier: MIT
// The ROS 1 message definitions of a sonarsynth bag, their MD5 sums and full texts
// (docs/rosbag.md, "Message definitions").
#include "sonarsynth/formats/rosbag/messages.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sonarsynth/error.hpp"

namespace sonarsynth::rosbag {
namespace {

// The .msg files, byte for byte. std_msgs 0.5.13, geometry_msgs, sensor_msgs 1.13.1 and tf2_msgs
// 0.7.6 as Debian 12's python3-*-msgs packages carry them (their classes' _full_text);
// marine_acoustic_msgs 2.0.2 (ROS 1, the catkin package of github.com/apl-ocean-iss/marine_msgs).
constexpr std::array<MessageText, 13> kTexts = {{
    {"std_msgs/Header",
     R"msg(# Standard metadata for higher-level stamped data types.
# This is generally used to communicate timestamped data 
# in a particular coordinate frame.
# 
# sequence ID: consecutively increasing ID 
uint32 seq
#Two-integer timestamp that is expressed as:
# * stamp.sec: seconds (stamp_secs) since epoch (in Python the variable is called 'secs')
# * stamp.nsec: nanoseconds since stamp_secs (in Python the variable is called 'nsecs')
# time-handling sugar is provided by the client library
time stamp
#Frame this data is associated with
string frame_id
)msg"},
    {"geometry_msgs/Vector3",
     R"msg(# This represents a vector in free space. 
# It is only meant to represent a direction. Therefore, it does not
# make sense to apply a translation to it (e.g., when applying a 
# generic rigid transformation to a Vector3, tf2 will only apply the
# rotation). If you want your data to be translatable too, use the
# geometry_msgs/Point message instead.

float64 x
float64 y
float64 z)msg"},
    {"geometry_msgs/Quaternion",
     R"msg(# This represents an orientation in free space in quaternion form.

float64 x
float64 y
float64 z
float64 w
)msg"},
    {"geometry_msgs/Transform",
     R"msg(# This represents the transform between two coordinate frames in free space.

Vector3 translation
Quaternion rotation
)msg"},
    {"geometry_msgs/TransformStamped",
     R"msg(# This expresses a transform from coordinate frame header.frame_id
# to the coordinate frame child_frame_id
#
# This message is mostly used by the 
# <a href="http://wiki.ros.org/tf">tf</a> package. 
# See its documentation for more information.

Header header
string child_frame_id # the frame id of the child frame
Transform transform
)msg"},
    {"tf2_msgs/TFMessage",
     R"msg(geometry_msgs/TransformStamped[] transforms
)msg"},
    {"sensor_msgs/NavSatStatus",
     R"msg(# Navigation Satellite fix status for any Global Navigation Satellite System

# Whether to output an augmented fix is determined by both the fix
# type and the last time differential corrections were received.  A
# fix is valid when status >= STATUS_FIX.

int8 STATUS_NO_FIX =  -1        # unable to fix position
int8 STATUS_FIX =      0        # unaugmented fix
int8 STATUS_SBAS_FIX = 1        # with satellite-based augmentation
int8 STATUS_GBAS_FIX = 2        # with ground-based augmentation

int8 status

# Bits defining which Global Navigation Satellite System signals were
# used by the receiver.

uint16 SERVICE_GPS =     1
uint16 SERVICE_GLONASS = 2
uint16 SERVICE_COMPASS = 4      # includes BeiDou.
uint16 SERVICE_GALILEO = 8

uint16 service
)msg"},
    {"sensor_msgs/NavSatFix",
     R"msg(# Navigation Satellite fix for any Global Navigation Satellite System
#
# Specified using the WGS 84 reference ellipsoid

# header.stamp specifies the ROS time for this measurement (the
#        corresponding satellite time may be reported using the
#        sensor_msgs/TimeReference message).
#
# header.frame_id is the frame of reference reported by the satellite
#        receiver, usually the location of the antenna.  This is a
#        Euclidean frame relative to the vehicle, not a reference
#        ellipsoid.
Header header

# satellite fix status information
NavSatStatus status

# Latitude [degrees]. Positive is north of equator; negative is south.
float64 latitude

# Longitude [degrees]. Positive is east of prime meridian; negative is west.
float64 longitude

# Altitude [m]. Positive is above the WGS 84 ellipsoid
# (quiet NaN if no altitude is available).
float64 altitude

# Position covariance [m^2] defined relative to a tangential plane
# through the reported position. The components are East, North, and
# Up (ENU), in row-major order.
#
# Beware: this coordinate system exhibits singularities at the poles.

float64[9] position_covariance

# If the covariance of the fix is known, fill it in completely. If the
# GPS receiver provides the variance of each measurement, put them
# along the diagonal. If only Dilution of Precision is available,
# estimate an approximate covariance from that.

uint8 COVARIANCE_TYPE_UNKNOWN = 0
uint8 COVARIANCE_TYPE_APPROXIMATED = 1
uint8 COVARIANCE_TYPE_DIAGONAL_KNOWN = 2
uint8 COVARIANCE_TYPE_KNOWN = 3

uint8 position_covariance_type
)msg"},
    {"sensor_msgs/Imu",
     R"msg(# This is a message to hold data from an IMU (Inertial Measurement Unit)
#
# Accelerations should be in m/s^2 (not in g's), and rotational velocity should be in rad/sec
#
# If the covariance of the measurement is known, it should be filled in (if all you know is the 
# variance of each measurement, e.g. from the datasheet, just put those along the diagonal)
# A covariance matrix of all zeros will be interpreted as "covariance unknown", and to use the
# data a covariance will have to be assumed or gotten from some other source
#
# If you have no estimate for one of the data elements (e.g. your IMU doesn't produce an orientation 
# estimate), please set element 0 of the associated covariance matrix to -1
# If you are interpreting this message, please check for a value of -1 in the first element of each 
# covariance matrix, and disregard the associated estimate.

Header header

geometry_msgs/Quaternion orientation
float64[9] orientation_covariance # Row major about x, y, z axes

geometry_msgs/Vector3 angular_velocity
float64[9] angular_velocity_covariance # Row major about x, y, z axes

geometry_msgs/Vector3 linear_acceleration
float64[9] linear_acceleration_covariance # Row major x, y z 
)msg"},
    {"marine_acoustic_msgs/PingInfo",
     R"msg(# Center frequency of sonar in Hz
# Set to 0 if unavailable
float32 frequency

# Speed of sound (m/s) used to calculate ranges;
# Set to 0 if unavailable
float32 sound_speed

# Sonar reported -3db beamwidths
# May be empty if not reported
# reported in radians
float32[] tx_beamwidths
float32[] rx_beamwidths
)msg"},
    {"marine_acoustic_msgs/SonarImageData",
     R"msg(bool    is_bigendian

uint32  DTYPE_UINT8 = 0
uint32  DTYPE_INT8 = 1
uint32  DTYPE_UINT16 = 2
uint32  DTYPE_INT16 = 3
uint32  DTYPE_UINT32 = 4
uint32  DTYPE_INT32 = 5
uint32  DTYPE_UINT64 = 6
uint32  DTYPE_INT64 = 7
uint32  DTYPE_FLOAT32 = 8
uint32  DTYPE_FLOAT64 = 9

uint32  dtype

# the number of beams associated with the image
uint32 beam_count

# The actually pixel data in row-major (beam_index major) format
uint8[] data
)msg"},
    {"marine_acoustic_msgs/RawSonarImage",
     R"msg(
# The header time should be the time the ping was transmitted, not
# the time the message was received.
# Note that these two could potentially be several seconds apart,
# especially in deep water.
std_msgs/Header header

PingInfo ping_info

float32 sample_rate   # hz

uint32  samples_per_beam  # the number of samples in each beam

# Many sonars have some kind of upper gate for water column data
# this represents the sample number of the first non empty sample
# for beam n
uint32 sample0

# Multi-sector multibeams can transmit different sectors at different times
# The Reson doesn't but we include a TX delay for each beam anyway.
#
# Overall, therefore, our overall time is:
#
# header.stamp: TX cycle starts
# Each beam's TX time: header.stamp + transmit_delay[i]
# Each beam's RX time: header.stamp + transmit_delay[i] + sample_rate*image_row
float32[] tx_delays
# Steering angle applied to tx beam
# reported in radians
float32[] tx_angles

# Steering angle applied to rx beam
# reported in radians
float32[] rx_angles

SonarImageData image
)msg"},
    // sonarsynth's own (docs/robotics.md, "Truth topics"); formats/mcap/ros2_messages.cpp has
    // the ROS 2 text, the same fields without the comments.
    {"sonarsynth_msgs/SideScanTruth",
     R"msg(# Per-sample truth of one side of a sonarsynth ping: element i of each array is
# sample i (near -> far) of the RawSonarImage with the same stamp and frame_id.
uint8 CLASS_WATER_COLUMN = 0  # before the first seabed return: no return
uint8 CLASS_SEABED = 1        # dominated by the seabed (label 0)
uint8 CLASS_OBJECT = 2        # dominated by an object (label > 0)
uint8 CLASS_SHADOW = 3        # no return: occluded seabed
uint8 CLASS_NO_SEABED = 4     # no return: no seabed (a hole, beyond the bathymetry)
int32 LABEL_NONE = -1
Header header
uint32 samples                # the length of each array
uint8[] sample_class          # CLASS_*
int32[] label                 # object id, 0 seabed; of a shadow its caster; LABEL_NONE none
float32[] grazing_rad         # grazing angle on the seabed, rad; NaN where none
float32[] ground_range_m      # horizontal distance from nadir across track, m; NaN where none
)msg"},
}};

constexpr std::array<std::string_view, 16> kBuiltins = {
    "bool",   "int8",    "uint8",   "int16",  "uint16", "int32",    "uint32", "int64",
    "uint64", "float32", "float64", "string", "time",   "duration", "char",   "byte"};

bool is_builtin(std::string_view t) {
  return std::find(kBuiltins.begin(), kBuiltins.end(), t) != kBuiltins.end();
}

std::string_view trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

/// One non-empty line of a .msg file without its comment: a field or a constant.
struct Line {
  std::string type;   ///< as written, with any array suffix
  std::string name;   ///< field or constant name
  std::string value;  ///< constants only: the value, whitespace removed
  bool constant = false;
};

/// The fields and constants of a .msg text (string constants, which keep '#', are not used
/// by the types here and are not supported).
std::vector<Line> parse(std::string_view text) {
  std::vector<Line> out;
  while (!text.empty()) {
    const auto nl = text.find('\n');
    std::string_view raw = text.substr(0, nl);
    text = nl == std::string_view::npos ? std::string_view{} : text.substr(nl + 1);
    const std::string_view line = trim(raw.substr(0, raw.find('#')));
    if (line.empty()) continue;
    const auto sp = line.find_first_of(" \t");
    Line l;
    l.type = std::string(line.substr(0, sp));
    const std::string_view rest =
        trim(line.substr(sp == std::string_view::npos ? line.size() : sp));
    const auto eq = rest.find('=');
    if (eq == std::string_view::npos) {
      l.name = std::string(rest);
    } else {
      l.constant = true;
      l.name = std::string(trim(rest.substr(0, eq)));
      for (char c : rest.substr(eq + 1)) {
        if (c != ' ' && c != '\t' && c != '\r') l.value += c;
      }
    }
    out.push_back(std::move(l));
  }
  return out;
}

/// The message type a field type names ("Header" is std_msgs/Header; a name without a package
/// is in `package`), without an array suffix; empty for built-in types.
std::string field_message_type(std::string_view field_type, std::string_view package) {
  const std::string_view base = field_type.substr(0, field_type.find('['));
  if (is_builtin(base)) return {};
  if (base == "Header") return "std_msgs/Header";
  if (base.find('/') != std::string_view::npos) return std::string(base);
  return std::string(package) + "/" + std::string(base);
}

std::string_view text_of(std::string_view type, std::span<const MessageText> texts) {
  for (const MessageText& t : texts) {
    if (t.type == type) return t.text;
  }
  throw Error("rosbag: no message definition for type '" + std::string(type) + "'");
}

std::string_view package_of(std::string_view type) {
  return type.substr(0, type.find('/'));
}

void add_dependencies(std::string_view type, std::span<const MessageText> texts,
                      std::vector<std::string>& deps) {
  for (const Line& l : parse(text_of(type, texts))) {
    if (l.constant) continue;
    const std::string sub = field_message_type(l.type, package_of(type));
    if (sub.empty() || std::find(deps.begin(), deps.end(), sub) != deps.end()) continue;
    deps.push_back(sub);
    add_dependencies(sub, texts, deps);
  }
}

// RFC 1321 MD5, byte order of its words little-endian.
constexpr std::array<std::uint32_t, 64> kK = {
    0xd76aa478, 0xe8c7b756, 0x242070db, 0xc1bdceee, 0xf57c0faf, 0x4787c62a, 0xa8304613, 0xfd469501,
    0x698098d8, 0x8b44f7af, 0xffff5bb1, 0x895cd7be, 0x6b901122, 0xfd987193, 0xa679438e, 0x49b40821,
    0xf61e2562, 0xc040b340, 0x265e5a51, 0xe9b6c7aa, 0xd62f105d, 0x02441453, 0xd8a1e681, 0xe7d3fbc8,
    0x21e1cde6, 0xc33707d6, 0xf4d50d87, 0x455a14ed, 0xa9e3e905, 0xfcefa3f8, 0x676f02d9, 0x8d2a4c8a,
    0xfffa3942, 0x8771f681, 0x6d9d6122, 0xfde5380c, 0xa4beea44, 0x4bdecfa9, 0xf6bb4b60, 0xbebfbc70,
    0x289b7ec6, 0xeaa127fa, 0xd4ef3085, 0x04881d05, 0xd9d4d039, 0xe6db99e5, 0x1fa27cf8, 0xc4ac5665,
    0xf4292244, 0x432aff97, 0xab9423a7, 0xfc93a039, 0x655b59c3, 0x8f0ccc92, 0xffeff47d, 0x85845dd1,
    0x6fa87e4f, 0xfe2ce6e0, 0xa3014314, 0x4e0811a1, 0xf7537e82, 0xbd3af235, 0x2ad7d2bb, 0xeb86d391};
constexpr std::array<std::uint32_t, 64> kShift = {
    7,  12, 17, 22, 7,  12, 17, 22, 7,  12, 17, 22, 7,  12, 17, 22, 5,  9,  14, 20, 5,  9,
    14, 20, 5,  9,  14, 20, 5,  9,  14, 20, 4,  11, 16, 23, 4,  11, 16, 23, 4,  11, 16, 23,
    4,  11, 16, 23, 6,  10, 15, 21, 6,  10, 15, 21, 6,  10, 15, 21, 6,  10, 15, 21};

std::uint32_t rotl(std::uint32_t x, std::uint32_t c) {
  return (x << c) | (x >> (32 - c));
}

void md5_block(std::array<std::uint32_t, 4>& h, const std::uint8_t* p) {
  std::array<std::uint32_t, 16> m{};
  for (std::size_t i = 0; i < 16; ++i) {
    m[i] = static_cast<std::uint32_t>(p[4 * i]) | static_cast<std::uint32_t>(p[4 * i + 1]) << 8 |
           static_cast<std::uint32_t>(p[4 * i + 2]) << 16 |
           static_cast<std::uint32_t>(p[4 * i + 3]) << 24;
  }
  std::uint32_t a = h[0], b = h[1], c = h[2], d = h[3];
  for (std::uint32_t i = 0; i < 64; ++i) {
    std::uint32_t f = 0, g = 0;
    if (i < 16) {
      f = (b & c) | (~b & d);
      g = i;
    } else if (i < 32) {
      f = (d & b) | (~d & c);
      g = (5 * i + 1) % 16;
    } else if (i < 48) {
      f = b ^ c ^ d;
      g = (3 * i + 5) % 16;
    } else {
      f = c ^ (b | ~d);
      g = (7 * i) % 16;
    }
    const std::uint32_t t = d;
    d = c;
    c = b;
    b = b + rotl(a + f + kK[i] + m[g], kShift[i]);
    a = t;
  }
  h[0] += a;
  h[1] += b;
  h[2] += c;
  h[3] += d;
}

}  // namespace

std::span<const MessageText> message_texts() {
  return kTexts;
}

std::string md5_hex(std::string_view bytes) {
  std::array<std::uint32_t, 4> h = {0x67452301, 0xefcdab89, 0x98badcfe, 0x10325476};
  std::vector<std::uint8_t> msg(bytes.begin(), bytes.end());
  const std::uint64_t bits = static_cast<std::uint64_t>(bytes.size()) * 8;
  msg.push_back(0x80);
  while (msg.size() % 64 != 56) msg.push_back(0);
  for (int i = 0; i < 8; ++i) msg.push_back(static_cast<std::uint8_t>((bits >> (8 * i)) & 0xFFu));
  for (std::size_t off = 0; off < msg.size(); off += 64) md5_block(h, msg.data() + off);
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (std::uint32_t w : h) {
    for (int i = 0; i < 4; ++i) {
      const auto byte = (w >> (8 * i)) & 0xFFu;
      out += kHex[byte >> 4];
      out += kHex[byte & 0xFu];
    }
  }
  return out;
}

std::string message_md5(std::string_view type, std::span<const MessageText> texts) {
  const std::vector<Line> lines = parse(text_of(type, texts));
  std::string text;
  for (const Line& l : lines) {
    if (l.constant) text += l.type + " " + l.name + "=" + l.value + "\n";
  }
  for (const Line& l : lines) {
    if (l.constant) continue;
    const std::string sub = field_message_type(l.type, package_of(type));
    text += (sub.empty() ? l.type : message_md5(sub, texts)) + " " + l.name + "\n";
  }
  if (!text.empty()) text.pop_back();  // genmsg strips the last newline
  return md5_hex(text);
}

std::string message_definition(std::string_view type, std::span<const MessageText> texts) {
  std::vector<std::string> deps;
  add_dependencies(type, texts, deps);
  std::string out(text_of(type, texts));
  out += '\n';
  for (const std::string& d : deps) {
    out += std::string(80, '=') + "\nMSG: " + d + "\n";
    out += text_of(d, texts);
    out += '\n';
  }
  out.pop_back();  // as genpy: no separator newline after the last text
  return out;
}

}  // namespace sonarsynth::rosbag
