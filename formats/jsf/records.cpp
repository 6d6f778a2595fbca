// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/jsf/records.hpp"

#include <algorithm>
#include <string_view>

namespace sonarsynth::jsf {

const char* message_type_name(std::uint16_t type) {
  switch (type) {
    case 40:
      return "sonar message status";
    case 80:
      return "sonar data";
    case 82:
      return "side scan data (old)";
    case 86:
      return "4400-SAS processed data";
    case 181:
      return "navigation offsets";
    case 182:
      return "system information";
    case 426:
      return "file timestamp";
    case 428:
      return "file padding";
    case 1260:
      return "target file data";
    case 2000:
      return "serial port raw data";
    case 2002:
      return "NMEA string";
    case 2020:
      return "pitch/roll";
    case 2040:
      return "miscellaneous analog sensors";
    case 2060:
      return "pressure sensor";
    case 2080:
      return "Doppler velocity log";
    case 2090:
      return "situation";
    case 2091:
      return "situation comprehensive";
    case 9999:
      return "sonarsynth XTF ping fields";
    case 2100:
      return "cable counter";
    case 2101:
      return "kilometre of pipe";
    case 2111:
      return "container timestamp";
    default:
      break;
  }
  return nullptr;
}

namespace {
constexpr std::string_view kXtfTag = "sonarsynth-xtf";

void encode_tag(ByteWriter& w) {
  std::array<char, 16> tag{};
  std::copy(kXtfTag.begin(), kXtfTag.end(), tag.begin());
  w.chars(tag);
  w.u32(XtfFileFields::kLayout);
}

bool decode_tag(ByteReader& r) {
  std::array<char, 16> tag{};
  r.chars(tag);
  const std::uint32_t layout = r.u32();
  return std::string_view(tag.data(), kXtfTag.size()) == kXtfTag && tag[kXtfTag.size()] == 0 &&
         layout == XtfFileFields::kLayout;
}

template <class Record>
void encode_tagged(ByteWriter& w, const Record& rec) {
  encode_tag(w);
  write_fields(w, rec);
}

/// False (with the tag and layout consumed) if the bytes do not start with them.
template <class Record>
bool decode_tagged(ByteReader& r, Record& rec) {
  if (!decode_tag(r)) return false;
  FieldReader io(r);
  Record::fields(io, rec);
  return true;
}
}  // namespace

void XtfFileFields::encode(ByteWriter& w) const {
  encode_tagged(w, *this);
}
bool XtfFileFields::decode(ByteReader& r, XtfFileFields& f) {
  return decode_tagged(r, f);
}
void XtfPingFields::encode(ByteWriter& w) const {
  encode_tagged(w, *this);
}
bool XtfPingFields::decode(ByteReader& r, XtfPingFields& f) {
  return decode_tagged(r, f);
}

// Each field table covers exactly its record's documented size.
static_assert(field_table_size<MessageHeader>() == MessageHeader::kSize);
static_assert(field_table_size<SonarDataHeader>() == SonarDataHeader::kSize);
static_assert(field_table_size<SystemInformation>() == SystemInformation::kSize);
static_assert(kXtfTagSize + field_table_size<XtfFileFields>() == XtfFileFields::kSize);
static_assert(kXtfTagSize + field_table_size<XtfPingFields>() == XtfPingFields::kSize);

}  // namespace sonarsynth::jsf
