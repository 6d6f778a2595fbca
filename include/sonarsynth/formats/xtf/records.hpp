// SPDX-License-Identifier: MIT
#pragma once

// XTF (eXtended Triton Format) records, laid out as the Triton XTF specification (Rev. 41) and
// docs/xtf.md §1 describe them. Each struct keeps the spec's field names
// and order, has kSize (its exact size in bytes) and encodes/decodes field by field in explicit
// little-endian through ByteWriter/ByteReader. No struct is ever cast from raw bytes.
// Units are those of the file (degrees, knots, decimetres...); conversion to radians and SI
// units happens in writer.cpp / reader.cpp.

#include <array>
#include <cstddef>
#include <cstdint>

#include "sonarsynth/formats/io/byte_io.hpp"

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

  void encode(ByteWriter& w) const;
  static XtfChanInfo decode(ByteReader& r);
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

  void encode(ByteWriter& w) const;
  static XtfFileHeader decode(ByteReader& r);
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

  void encode(ByteWriter& w) const;
  static XtfPacketHeader decode(ByteReader& r);
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

  void encode(ByteWriter& w) const;
  static XtfPingHeader decode(ByteReader& r);
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

  void encode(ByteWriter& w) const;
  static XtfPingChanHeader decode(ByteReader& r);
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

  void encode(ByteWriter& w) const;
  static XtfNotesHeader decode(ByteReader& r);
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

  void encode(ByteWriter& w) const;
  static XtfAttitudeData decode(ByteReader& r);
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

  void encode(ByteWriter& w) const;
  static XtfHeaderNavigation decode(ByteReader& r);
  bool operator==(const XtfHeaderNavigation&) const = default;
};

}  // namespace sonarsynth::xtf
