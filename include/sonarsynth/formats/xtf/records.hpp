// SPDX-License-Identifier: MIT
#pragma once

// XTF (eXtended Triton Format) records, laid out as the Triton XTF specification (Rev. 41) and
// docs/xtf.md §1 describe them. Each struct keeps the spec's field names and order, has kSize
// (its exact size in bytes) and lists its fields once, with their widths, in a field table
// (`fields`, io/fields.hpp) that both encode and decode walk, field by field in explicit
// little-endian through ByteWriter/ByteReader. No struct is ever cast from raw bytes.
// Units are those of the file (degrees, knots, decimetres...); conversion to radians and SI
// units happens in writer.cpp / reader.cpp.

#include <array>
#include <cstddef>
#include <cstdint>

#include "sonarsynth/formats/io/byte_io.hpp"
#include "sonarsynth/formats/io/fields.hpp"

namespace sonarsynth::xtf {

inline constexpr std::uint8_t kFileFormat = 0x7B;      ///< XTFFILEHEADER.FileFormat
inline constexpr std::uint16_t kMagicNumber = 0xFACE;  ///< first WORD of every packet
inline constexpr std::size_t kPacketAlignment = 64;    ///< Isis pads every packet to 64 bytes
inline constexpr std::size_t kChanInfoPerFileHeader = 6;
inline constexpr std::size_t kChanInfoPerExtraBlock = 8;  ///< per extra 1024-byte header block

/// HeaderType codes (spec Rev. 41 + later sections) this project names.
enum class HeaderType : std::uint8_t {
  kSonar = 0,
  kNotes = 1,
  kBathy = 2,
  kAttitude = 3,
  kForward = 4,
  kElac = 5,
  kRawSerial = 6,
  kEmbedHead = 7,
  kHiddenSonar = 8,
  kNavigation = 42,
  kSourceTimeGyro = 84,
  kPosRawNavigation = 107,
  kCustom = 199,
  kUserDefined = 200,
};

/// A short name for a HeaderType code ("SONAR", "NOTES", ... "TYPE_17" for unnamed ones).
const char* header_type_name(std::uint8_t header_type);

/// CHANINFO.TypeOfChannel.
enum class ChannelType : std::uint8_t {
  kSubbottom = 0,
  kPort = 1,
  kStarboard = 2,
  kBathymetry = 3
};

/// CHANINFO.SampleFormat (Rev. 41, byte 74).
enum class SampleFormatCode : std::uint8_t {
  kLegacy = 0,  ///< use BytesPerSample (integers)
  kIbmFloat32 = 1,
  kInt32 = 2,
  kInt16 = 3,
  kIeeeFloat32 = 5,
  kInt8 = 8,
};

/// CHANINFO — 128 bytes, inside the file header at 256 + 128 i.
struct XtfChanInfo {
  static constexpr std::size_t kSize = 128;
  std::uint8_t TypeOfChannel = 0;
  std::uint8_t SubChannelNumber = 0;
  std::uint16_t CorrectionFlags = 0;
  std::uint16_t UniPolar = 0;
  std::uint16_t BytesPerSample = 0;
  std::uint32_t Reserved = 0;  ///< formerly SamplesPerChannel
  std::array<char, 16> ChannelName{};
  float VoltScale = 0.0f;
  float Frequency = 0.0f;
  float HorizBeamAngle = 0.0f;
  float TiltAngle = 0.0f;
  float BeamWidth = 0.0f;
  float OffsetX = 0.0f;
  float OffsetY = 0.0f;
  float OffsetZ = 0.0f;
  float OffsetYaw = 0.0f;
  float OffsetPitch = 0.0f;
  float OffsetRoll = 0.0f;
  std::uint16_t BeamsPerArray = 0;
  std::uint8_t SampleFormat = 0;
  std::array<std::uint8_t, 53> ReservedArea2{};

  template <class IO, class Self>
  static constexpr void fields(IO& io, Self& s) {
    io.u8(s.TypeOfChannel);
    io.u8(s.SubChannelNumber);
    io.u16(s.CorrectionFlags);
    io.u16(s.UniPolar);
    io.u16(s.BytesPerSample);
    io.u32(s.Reserved);
    io.chars(s.ChannelName);
    io.f32(s.VoltScale);
    io.f32(s.Frequency);
    io.f32(s.HorizBeamAngle);
    io.f32(s.TiltAngle);
    io.f32(s.BeamWidth);
    io.f32(s.OffsetX);
    io.f32(s.OffsetY);
    io.f32(s.OffsetZ);
    io.f32(s.OffsetYaw);
    io.f32(s.OffsetPitch);
    io.f32(s.OffsetRoll);
    io.u16(s.BeamsPerArray);
    io.u8(s.SampleFormat);
    io.bytes(s.ReservedArea2);
  }
  void encode(ByteWriter& w) const { write_fields(w, *this); }
  static XtfChanInfo decode(ByteReader& r) { return read_fields<XtfChanInfo>(r); }
  bool operator==(const XtfChanInfo&) const = default;
};

/// XTFFILEHEADER — 1024 bytes with six CHANINFO. Further CHANINFO (channels > 6) follow in
/// 1024-byte blocks of eight; see encode_extra_chan_info_blocks().
struct XtfFileHeader {
  static constexpr std::size_t kSize = 1024;
  std::uint8_t FileFormat = kFileFormat;
  std::uint8_t SystemType = 1;
  std::array<char, 8> RecordingProgramName{};
  std::array<char, 8> RecordingProgramVersion{};
  std::array<char, 16> SonarName{};
  std::uint16_t SonarType = 0;
  std::array<char, 64> NoteString{};
  std::array<char, 64> ThisFileName{};
  std::uint16_t NavUnits = 0;
  std::uint16_t NumberOfSonarChannels = 0;
  std::uint16_t NumberOfBathymetryChannels = 0;
  std::uint8_t NumberOfSnippetChannels = 0;
  std::uint8_t NumberOfForwardLookArrays = 0;
  std::uint16_t NumberOfEchoStrengthChannels = 0;
  std::uint8_t NumberOfInterferometryChannels = 0;
  std::uint8_t Reserved1 = 0;
  std::uint16_t Reserved2 = 0;
  float ReferencePointHeight = 0.0f;
  std::array<std::uint8_t, 12> ProjectionType{};
  std::array<std::uint8_t, 10> SpheriodType{};  // [sic], as the spec spells it
  std::int32_t NavigationLatency = 0;
  float OriginY = 0.0f;
  float OriginX = 0.0f;
  float NavOffsetY = 0.0f;
  float NavOffsetX = 0.0f;
  float NavOffsetZ = 0.0f;
  float NavOffsetYaw = 0.0f;
  float MRUOffsetY = 0.0f;
  float MRUOffsetX = 0.0f;
  float MRUOffsetZ = 0.0f;
  float MRUOffsetYaw = 0.0f;
  float MRUOffsetPitch = 0.0f;
  float MRUOffsetRoll = 0.0f;
  std::array<XtfChanInfo, kChanInfoPerFileHeader> ChanInfo{};

  template <class IO, class Self>
  static constexpr void fields(IO& io, Self& s) {
    io.u8(s.FileFormat);
    io.u8(s.SystemType);
    io.chars(s.RecordingProgramName);
    io.chars(s.RecordingProgramVersion);
    io.chars(s.SonarName);
    io.u16(s.SonarType);
    io.chars(s.NoteString);
    io.chars(s.ThisFileName);
    io.u16(s.NavUnits);
    io.u16(s.NumberOfSonarChannels);
    io.u16(s.NumberOfBathymetryChannels);
    io.u8(s.NumberOfSnippetChannels);
    io.u8(s.NumberOfForwardLookArrays);
    io.u16(s.NumberOfEchoStrengthChannels);
    io.u8(s.NumberOfInterferometryChannels);
    io.u8(s.Reserved1);
    io.u16(s.Reserved2);
    io.f32(s.ReferencePointHeight);
    io.bytes(s.ProjectionType);
    io.bytes(s.SpheriodType);
    io.i32(s.NavigationLatency);
    io.f32(s.OriginY);
    io.f32(s.OriginX);
    io.f32(s.NavOffsetY);
    io.f32(s.NavOffsetX);
    io.f32(s.NavOffsetZ);
    io.f32(s.NavOffsetYaw);
    io.f32(s.MRUOffsetY);
    io.f32(s.MRUOffsetX);
    io.f32(s.MRUOffsetZ);
    io.f32(s.MRUOffsetYaw);
    io.f32(s.MRUOffsetPitch);
    io.f32(s.MRUOffsetRoll);
    for (auto& c : s.ChanInfo) XtfChanInfo::fields(io, c);
  }
  void encode(ByteWriter& w) const { write_fields(w, *this); }
  static XtfFileHeader decode(ByteReader& r) { return read_fields<XtfFileHeader>(r); }
  bool operator==(const XtfFileHeader&) const = default;

  /// Sum of every channel count in the header (sonar + bathymetry + snippet + forward-look +
  /// echo strength + interferometry): the number of CHANINFO the file carries.
  std::uint32_t total_channels() const;
  /// Number of extra 1024-byte CHANINFO blocks that follow the header for `total_channels`.
  static std::uint32_t extra_blocks(std::uint32_t total_channels);
};

/// The first 14 bytes of every packet.
struct XtfPacketHeader {
  static constexpr std::size_t kSize = 14;
  std::uint16_t MagicNumber = kMagicNumber;
  std::uint8_t HeaderType = 0;
  std::uint8_t SubChannelNumber = 0;
  std::uint16_t NumChansToFollow = 0;
  std::array<std::uint16_t, 2> Reserved1{};
  std::uint32_t NumBytesThisRecord = 0;

  template <class IO, class Self>
  static constexpr void fields(IO& io, Self& s) {
    io.u16(s.MagicNumber);
    io.u8(s.HeaderType);
    io.u8(s.SubChannelNumber);
    io.u16(s.NumChansToFollow);
    io.u16(s.Reserved1[0]);
    io.u16(s.Reserved1[1]);
    io.u32(s.NumBytesThisRecord);
  }
  void encode(ByteWriter& w) const { write_fields(w, *this); }
  static XtfPacketHeader decode(ByteReader& r) { return read_fields<XtfPacketHeader>(r); }
  bool operator==(const XtfPacketHeader&) const = default;
};

/// XTFPINGHEADER (= XTFBATHHEADER) — 256 bytes, HeaderType 0 for side-scan.
struct XtfPingHeader {
  static constexpr std::size_t kSize = 256;
  XtfPacketHeader Header;  ///< bytes 0..13
  std::uint16_t Year = 0;
  std::uint8_t Month = 0;
  std::uint8_t Day = 0;
  std::uint8_t Hour = 0;
  std::uint8_t Minute = 0;
  std::uint8_t Second = 0;
  std::uint8_t HSeconds = 0;
  std::uint16_t JulianDay = 0;
  std::uint32_t EventNumber = 0;
  std::uint32_t PingNumber = 0;
  float SoundVelocity = 0.0f;
  float OceanTide = 0.0f;
  std::uint32_t Reserved2 = 0;
  float ConductivityFreq = 0.0f;
  float TemperatureFreq = 0.0f;
  float PressureFreq = 0.0f;
  float PressureTemp = 0.0f;
  float Conductivity = 0.0f;
  float WaterTemperature = 0.0f;
  float Pressure = 0.0f;
  float ComputedSoundVelocity = 0.0f;
  float MagX = 0.0f;
  float MagY = 0.0f;
  float MagZ = 0.0f;
  float AuxVal1 = 0.0f;
  float AuxVal2 = 0.0f;
  float AuxVal3 = 0.0f;
  float AuxVal4 = 0.0f;
  float AuxVal5 = 0.0f;
  float AuxVal6 = 0.0f;
  float SpeedLog = 0.0f;
  float Turbidity = 0.0f;
  float ShipSpeed = 0.0f;
  float ShipGyro = 0.0f;
  double ShipYcoordinate = 0.0;
  double ShipXcoordinate = 0.0;
  std::uint16_t ShipAltitude = 0;
  std::uint16_t ShipDepth = 0;
  std::uint8_t FixTimeHour = 0;
  std::uint8_t FixTimeMinute = 0;
  std::uint8_t FixTimeSecond = 0;
  std::uint8_t FixTimeHsecond = 0;
  float SensorSpeed = 0.0f;
  float KP = 0.0f;
  double SensorYcoordinate = 0.0;
  double SensorXcoordinate = 0.0;
  std::uint16_t SonarStatus = 0;
  std::uint16_t RangeToFish = 0;
  std::uint16_t BearingToFish = 0;
  std::uint16_t CableOut = 0;
  float Layback = 0.0f;
  float CableTension = 0.0f;
  float SensorDepth = 0.0f;
  float SensorPrimaryAltitude = 0.0f;
  float SensorAuxAltitude = 0.0f;
  float SensorPitch = 0.0f;
  float SensorRoll = 0.0f;
  float SensorHeading = 0.0f;
  float Heave = 0.0f;
  float Yaw = 0.0f;
  std::uint32_t AttitudeTimeTag = 0;
  float DOT = 0.0f;
  std::uint32_t NavFixMilliseconds = 0;
  std::uint8_t ComputerClockHour = 0;
  std::uint8_t ComputerClockMinute = 0;
  std::uint8_t ComputerClockSecond = 0;
  std::uint8_t ComputerClockHsec = 0;
  std::int16_t FishPositionDeltaX = 0;
  std::int16_t FishPositionDeltaY = 0;
  std::uint8_t FishPositionErrorCode = 0;
  std::uint32_t OptionalOffset = 0;
  std::uint8_t CableOutHundredths = 0;
  std::array<std::uint8_t, 6> ReservedSpace2{};

  template <class IO, class Self>
  static constexpr void fields(IO& io, Self& s) {
    XtfPacketHeader::fields(io, s.Header);
    io.u16(s.Year);
    io.u8(s.Month);
    io.u8(s.Day);
    io.u8(s.Hour);
    io.u8(s.Minute);
    io.u8(s.Second);
    io.u8(s.HSeconds);
    io.u16(s.JulianDay);
    io.u32(s.EventNumber);
    io.u32(s.PingNumber);
    io.f32(s.SoundVelocity);
    io.f32(s.OceanTide);
    io.u32(s.Reserved2);
    io.f32(s.ConductivityFreq);
    io.f32(s.TemperatureFreq);
    io.f32(s.PressureFreq);
    io.f32(s.PressureTemp);
    io.f32(s.Conductivity);
    io.f32(s.WaterTemperature);
    io.f32(s.Pressure);
    io.f32(s.ComputedSoundVelocity);
    io.f32(s.MagX);
    io.f32(s.MagY);
    io.f32(s.MagZ);
    io.f32(s.AuxVal1);
    io.f32(s.AuxVal2);
    io.f32(s.AuxVal3);
    io.f32(s.AuxVal4);
    io.f32(s.AuxVal5);
    io.f32(s.AuxVal6);
    io.f32(s.SpeedLog);
    io.f32(s.Turbidity);
    io.f32(s.ShipSpeed);
    io.f32(s.ShipGyro);
    io.f64(s.ShipYcoordinate);
    io.f64(s.ShipXcoordinate);
    io.u16(s.ShipAltitude);
    io.u16(s.ShipDepth);
    io.u8(s.FixTimeHour);
    io.u8(s.FixTimeMinute);
    io.u8(s.FixTimeSecond);
    io.u8(s.FixTimeHsecond);
    io.f32(s.SensorSpeed);
    io.f32(s.KP);
    io.f64(s.SensorYcoordinate);
    io.f64(s.SensorXcoordinate);
    io.u16(s.SonarStatus);
    io.u16(s.RangeToFish);
    io.u16(s.BearingToFish);
    io.u16(s.CableOut);
    io.f32(s.Layback);
    io.f32(s.CableTension);
    io.f32(s.SensorDepth);
    io.f32(s.SensorPrimaryAltitude);
    io.f32(s.SensorAuxAltitude);
    io.f32(s.SensorPitch);
    io.f32(s.SensorRoll);
    io.f32(s.SensorHeading);
    io.f32(s.Heave);
    io.f32(s.Yaw);
    io.u32(s.AttitudeTimeTag);
    io.f32(s.DOT);
    io.u32(s.NavFixMilliseconds);
    io.u8(s.ComputerClockHour);
    io.u8(s.ComputerClockMinute);
    io.u8(s.ComputerClockSecond);
    io.u8(s.ComputerClockHsec);
    io.i16(s.FishPositionDeltaX);
    io.i16(s.FishPositionDeltaY);
    io.u8(s.FishPositionErrorCode);
    io.u32(s.OptionalOffset);
    io.u8(s.CableOutHundredths);
    io.bytes(s.ReservedSpace2);
  }
  void encode(ByteWriter& w) const { write_fields(w, *this); }
  static XtfPingHeader decode(ByteReader& r) { return read_fields<XtfPingHeader>(r); }
  bool operator==(const XtfPingHeader&) const = default;
};

/// XTFPINGCHANHEADER — 64 bytes, before each channel's samples.
struct XtfPingChanHeader {
  static constexpr std::size_t kSize = 64;
  std::uint16_t ChannelNumber = 0;
  std::uint16_t DownsampleMethod = 0;
  float SlantRange = 0.0f;
  float GroundRange = 0.0f;
  float TimeDelay = 0.0f;
  float TimeDuration = 0.0f;
  float SecondsPerPing = 0.0f;
  std::uint16_t ProcessingFlags = 0;
  std::uint16_t Frequency = 0;
  std::uint16_t InitialGainCode = 0;
  std::uint16_t GainCode = 0;
  std::uint16_t BandWidth = 0;
  std::uint32_t ContactNumber = 0;
  std::uint16_t ContactClassification = 0;
  std::uint8_t ContactSubNumber = 0;
  std::uint8_t ContactType = 0;
  std::uint32_t NumSamples = 0;
  std::uint16_t MillivoltScale = 0;
  float ContactTimeOffTrack = 0.0f;
  std::uint8_t ContactCloseNumber = 0;
  std::uint8_t Reserved2 = 0;
  float FixedVSOP = 0.0f;
  std::int16_t Weight = 0;
  std::array<std::uint8_t, 4> ReservedSpace{};

  template <class IO, class Self>
  static constexpr void fields(IO& io, Self& s) {
    io.u16(s.ChannelNumber);
    io.u16(s.DownsampleMethod);
    io.f32(s.SlantRange);
    io.f32(s.GroundRange);
    io.f32(s.TimeDelay);
    io.f32(s.TimeDuration);
    io.f32(s.SecondsPerPing);
    io.u16(s.ProcessingFlags);
    io.u16(s.Frequency);
    io.u16(s.InitialGainCode);
    io.u16(s.GainCode);
    io.u16(s.BandWidth);
    io.u32(s.ContactNumber);
    io.u16(s.ContactClassification);
    io.u8(s.ContactSubNumber);
    io.u8(s.ContactType);
    io.u32(s.NumSamples);
    io.u16(s.MillivoltScale);
    io.f32(s.ContactTimeOffTrack);
    io.u8(s.ContactCloseNumber);
    io.u8(s.Reserved2);
    io.f32(s.FixedVSOP);
    io.i16(s.Weight);
    io.bytes(s.ReservedSpace);
  }
  void encode(ByteWriter& w) const { write_fields(w, *this); }
  static XtfPingChanHeader decode(ByteReader& r) { return read_fields<XtfPingChanHeader>(r); }
  bool operator==(const XtfPingChanHeader&) const = default;
};

/// XTFNOTESHEADER — 256 bytes, HeaderType 1.
struct XtfNotesHeader {
  static constexpr std::size_t kSize = 256;
  XtfPacketHeader Header;
  std::uint16_t Year = 0;
  std::uint8_t Month = 0;
  std::uint8_t Day = 0;
  std::uint8_t Hour = 0;
  std::uint8_t Minute = 0;
  std::uint8_t Second = 0;
  std::array<std::uint8_t, 35> ReservedBytes{};
  std::array<char, 200> NotesText{};

  template <class IO, class Self>
  static constexpr void fields(IO& io, Self& s) {
    XtfPacketHeader::fields(io, s.Header);
    io.u16(s.Year);
    io.u8(s.Month);
    io.u8(s.Day);
    io.u8(s.Hour);
    io.u8(s.Minute);
    io.u8(s.Second);
    io.bytes(s.ReservedBytes);
    io.chars(s.NotesText);
  }
  void encode(ByteWriter& w) const { write_fields(w, *this); }
  static XtfNotesHeader decode(ByteReader& r) { return read_fields<XtfNotesHeader>(r); }
  bool operator==(const XtfNotesHeader&) const = default;
};

/// XTFATTITUDEDATA — 64 bytes, HeaderType 3.
struct XtfAttitudeData {
  static constexpr std::size_t kSize = 64;
  XtfPacketHeader Header;
  std::array<std::uint32_t, 2> Reserved2{};
  std::uint32_t EpochMicroseconds = 0;
  std::uint32_t SourceEpoch = 0;
  float Pitch = 0.0f;
  float Roll = 0.0f;
  float Heave = 0.0f;
  float Yaw = 0.0f;
  std::uint32_t TimeTag = 0;
  float Heading = 0.0f;
  std::uint16_t Year = 0;
  std::uint8_t Month = 0;
  std::uint8_t Day = 0;
  std::uint8_t Hour = 0;
  std::uint8_t Minutes = 0;
  std::uint8_t Seconds = 0;
  std::uint16_t Milliseconds = 0;
  std::uint8_t Reserved3 = 0;

  template <class IO, class Self>
  static constexpr void fields(IO& io, Self& s) {
    XtfPacketHeader::fields(io, s.Header);
    io.u32(s.Reserved2[0]);
    io.u32(s.Reserved2[1]);
    io.u32(s.EpochMicroseconds);
    io.u32(s.SourceEpoch);
    io.f32(s.Pitch);
    io.f32(s.Roll);
    io.f32(s.Heave);
    io.f32(s.Yaw);
    io.u32(s.TimeTag);
    io.f32(s.Heading);
    io.u16(s.Year);
    io.u8(s.Month);
    io.u8(s.Day);
    io.u8(s.Hour);
    io.u8(s.Minutes);
    io.u8(s.Seconds);
    io.u16(s.Milliseconds);
    io.u8(s.Reserved3);
  }
  void encode(ByteWriter& w) const { write_fields(w, *this); }
  static XtfAttitudeData decode(ByteReader& r) { return read_fields<XtfAttitudeData>(r); }
  bool operator==(const XtfAttitudeData&) const = default;
};

/// XTFHEADERNAVIGATION — 64 bytes, HeaderType 42. Unlike other packets, bytes 3..9 are
/// Reserved[7] (no SubChannelNumber / NumChansToFollow).
struct XtfHeaderNavigation {
  static constexpr std::size_t kSize = 64;
  std::uint16_t MagicNumber = kMagicNumber;
  std::uint8_t HeaderType = static_cast<std::uint8_t>(xtf::HeaderType::kNavigation);
  std::array<std::uint8_t, 7> Reserved{};
  std::uint32_t NumBytesThisRecord = kSize;
  std::uint16_t Year = 0;
  std::uint8_t Month = 0;
  std::uint8_t Day = 0;
  std::uint8_t Hour = 0;
  std::uint8_t Minute = 0;
  std::uint8_t Second = 0;
  std::uint32_t Microseconds = 0;
  std::uint32_t SourceEpoch = 0;
  std::uint32_t TimeTag = 0;
  double RawYcoordinate = 0.0;
  double RawXcoordinate = 0.0;
  double RawAltitude = 0.0;
  std::uint8_t TimeFlag = 0;
  std::array<std::uint8_t, 6> Reserved1{};

  template <class IO, class Self>
  static constexpr void fields(IO& io, Self& s) {
    io.u16(s.MagicNumber);
    io.u8(s.HeaderType);
    io.bytes(s.Reserved);
    io.u32(s.NumBytesThisRecord);
    io.u16(s.Year);
    io.u8(s.Month);
    io.u8(s.Day);
    io.u8(s.Hour);
    io.u8(s.Minute);
    io.u8(s.Second);
    io.u32(s.Microseconds);
    io.u32(s.SourceEpoch);
    io.u32(s.TimeTag);
    io.f64(s.RawYcoordinate);
    io.f64(s.RawXcoordinate);
    io.f64(s.RawAltitude);
    io.u8(s.TimeFlag);
    io.bytes(s.Reserved1);
  }
  void encode(ByteWriter& w) const { write_fields(w, *this); }
  static XtfHeaderNavigation decode(ByteReader& r) { return read_fields<XtfHeaderNavigation>(r); }
  bool operator==(const XtfHeaderNavigation&) const = default;
};

}  // namespace sonarsynth::xtf
