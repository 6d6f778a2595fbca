// SPDX-License-Identifier: MIT
#pragma once

#include <span>
#include <string>
#include <string_view>

/// The ROS 1 message definitions a sonarsynth bag embeds, and the two things ROS 1 derives from a
/// definition: the MD5 sum that identifies the type and the full text with its dependencies
/// (docs/rosbag.md, "Message definitions").
namespace sonarsynth::rosbag {

/// One message type as its package's .msg file spells it.
struct MessageText {
  std::string_view type;  ///< "package/Name"
  std::string_view text;  ///< the .msg file's contents, byte for byte
};

/// Every message type the writer uses and their dependencies.
std::span<const MessageText> message_texts();

/// MD5 digest (RFC 1321) of `bytes` as 32 lower-case hex digits.
std::string md5_hex(std::string_view bytes);

/// The ROS 1 MD5 sum of `type` (one of message_texts()): the MD5 of its constants
/// ("type name=value") then its fields ("type name" for built-in types and arrays of them,
/// "<md5 of the field's message type> name" otherwise), one per line, as genmsg computes it.
/// `texts` resolves the field types. Throws Error for a type or field type not in `texts`.
std::string message_md5(std::string_view type,
                        std::span<const MessageText> texts = message_texts());

/// The definition ROS 1 tools embed (a connection's message_definition): the text of `type`,
/// then per dependency (depth first, in field order, each once) a line of 80 '=', "MSG: <type>"
/// and its text.
std::string message_definition(std::string_view type,
                               std::span<const MessageText> texts = message_texts());

}  // namespace sonarsynth::rosbag
