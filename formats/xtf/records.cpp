// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/xtf/records.hpp"

#include <array>
#include <cstdio>

namespace sonarsynth::xtf {

const char* header_type_name(std::uint8_t header_type) {
  switch (header_type) {
    case 0:
      return "SONAR";
    case 1:
      return "NOTES";
    case 2:
      return "BATHY";
    case 3:
      return "ATTITUDE";
    case 4:
      return "FORWARD";
    case 5:
      return "ELAC";
    case 6:
      return "RAW_SERIAL";
    case 7:
      return "EMBED_HEAD";
    case 8:
      return "HIDDEN_SONAR";
    case 20:
      return "GPS";
    case 23:
      return "GYRO";
    case 42:
      return "NAVIGATION";
    case 50:
      return "TIME";
    case 84:
      return "SOURCETIME_GYRO";
    case 107:
      return "POS_RAW_NAVIGATION";
    case 199:
      return "CUSTOM";
    case 200:
      return "USERDEFINED";
    default:
      break;
  }
  static const std::array<std::array<char, 12>, 256> names = [] {
    std::array<std::array<char, 12>, 256> n{};
    for (std::size_t i = 0; i < n.size(); ++i) {
      std::snprintf(n[i].data(), n[i].size(), "TYPE_%zu", i);
    }
    return n;
  }();
  return names[header_type].data();
}

std::uint32_t XtfFileHeader::total_channels() const {
  return std::uint32_t{NumberOfSonarChannels} + NumberOfBathymetryChannels +
         NumberOfSnippetChannels + NumberOfForwardLookArrays + NumberOfEchoStrengthChannels +
         NumberOfInterferometryChannels;
}

std::uint32_t XtfFileHeader::extra_blocks(std::uint32_t total) {
  if (total <= kChanInfoPerFileHeader) return 0;
  const std::uint32_t extra = total - static_cast<std::uint32_t>(kChanInfoPerFileHeader);
  return (extra + static_cast<std::uint32_t>(kChanInfoPerExtraBlock) - 1) /
         static_cast<std::uint32_t>(kChanInfoPerExtraBlock);
}

// Each field table covers exactly its record's documented size.
static_assert(field_table_size<XtfChanInfo>() == XtfChanInfo::kSize);
static_assert(field_table_size<XtfFileHeader>() == XtfFileHeader::kSize);
static_assert(field_table_size<XtfPacketHeader>() == XtfPacketHeader::kSize);
static_assert(field_table_size<XtfPingHeader>() == XtfPingHeader::kSize);
static_assert(field_table_size<XtfPingChanHeader>() == XtfPingChanHeader::kSize);
static_assert(field_table_size<XtfNotesHeader>() == XtfNotesHeader::kSize);
static_assert(field_table_size<XtfAttitudeData>() == XtfAttitudeData::kSize);
static_assert(field_table_size<XtfHeaderNavigation>() == XtfHeaderNavigation::kSize);

}  // namespace sonarsynth::xtf
