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

// ---------------------------------------------------------------------------------------------
void XtfChanInfo::encode(ByteWriter& w) const {
  w.u8(TypeOfChannel);
  w.u8(SubChannelNumber);
  w.u16(CorrectionFlags);
  w.u16(UniPolar);
  w.u16(BytesPerSample);
  w.u32(Reserved);
  w.chars(ChannelName);
  w.f32(VoltScale);
  w.f32(Frequency);
  w.f32(HorizBeamAngle);
  w.f32(TiltAngle);
  w.f32(BeamWidth);
  w.f32(OffsetX);
  w.f32(OffsetY);
  w.f32(OffsetZ);
  w.f32(OffsetYaw);
  w.f32(OffsetPitch);
  w.f32(OffsetRoll);
  w.u16(BeamsPerArray);
  w.u8(SampleFormat);
  w.bytes(ReservedArea2);
}

XtfChanInfo XtfChanInfo::decode(ByteReader& r) {
  XtfChanInfo c;
  c.TypeOfChannel = r.u8();
  c.SubChannelNumber = r.u8();
  c.CorrectionFlags = r.u16();
  c.UniPolar = r.u16();
  c.BytesPerSample = r.u16();
  c.Reserved = r.u32();
  r.chars(c.ChannelName);
  c.VoltScale = r.f32();
  c.Frequency = r.f32();
  c.HorizBeamAngle = r.f32();
  c.TiltAngle = r.f32();
  c.BeamWidth = r.f32();
  c.OffsetX = r.f32();
  c.OffsetY = r.f32();
  c.OffsetZ = r.f32();
  c.OffsetYaw = r.f32();
  c.OffsetPitch = r.f32();
  c.OffsetRoll = r.f32();
  c.BeamsPerArray = r.u16();
  c.SampleFormat = r.u8();
  r.bytes(c.ReservedArea2);
  return c;
}

// ---------------------------------------------------------------------------------------------
void XtfFileHeader::encode(ByteWriter& w) const {
  w.u8(FileFormat);
  w.u8(SystemType);
  w.chars(RecordingProgramName);
  w.chars(RecordingProgramVersion);
  w.chars(SonarName);
  w.u16(SonarType);
  w.chars(NoteString);
  w.chars(ThisFileName);
  w.u16(NavUnits);
  w.u16(NumberOfSonarChannels);
  w.u16(NumberOfBathymetryChannels);
  w.u8(NumberOfSnippetChannels);
  w.u8(NumberOfForwardLookArrays);
  w.u16(NumberOfEchoStrengthChannels);
  w.u8(NumberOfInterferometryChannels);
  w.u8(Reserved1);
  w.u16(Reserved2);
  w.f32(ReferencePointHeight);
  w.bytes(ProjectionType);
  w.bytes(SpheriodType);
  w.i32(NavigationLatency);
  w.f32(OriginY);
  w.f32(OriginX);
  w.f32(NavOffsetY);
  w.f32(NavOffsetX);
  w.f32(NavOffsetZ);
  w.f32(NavOffsetYaw);
  w.f32(MRUOffsetY);
  w.f32(MRUOffsetX);
  w.f32(MRUOffsetZ);
  w.f32(MRUOffsetYaw);
  w.f32(MRUOffsetPitch);
  w.f32(MRUOffsetRoll);
  for (const auto& c : ChanInfo) c.encode(w);
}

XtfFileHeader XtfFileHeader::decode(ByteReader& r) {
  XtfFileHeader h;
  h.FileFormat = r.u8();
  h.SystemType = r.u8();
  r.chars(h.RecordingProgramName);
  r.chars(h.RecordingProgramVersion);
  r.chars(h.SonarName);
  h.SonarType = r.u16();
  r.chars(h.NoteString);
  r.chars(h.ThisFileName);
  h.NavUnits = r.u16();
  h.NumberOfSonarChannels = r.u16();
  h.NumberOfBathymetryChannels = r.u16();
  h.NumberOfSnippetChannels = r.u8();
  h.NumberOfForwardLookArrays = r.u8();
  h.NumberOfEchoStrengthChannels = r.u16();
  h.NumberOfInterferometryChannels = r.u8();
  h.Reserved1 = r.u8();
  h.Reserved2 = r.u16();
  h.ReferencePointHeight = r.f32();
  r.bytes(h.ProjectionType);
  r.bytes(h.SpheriodType);
  h.NavigationLatency = r.i32();
  h.OriginY = r.f32();
  h.OriginX = r.f32();
  h.NavOffsetY = r.f32();
  h.NavOffsetX = r.f32();
  h.NavOffsetZ = r.f32();
  h.NavOffsetYaw = r.f32();
  h.MRUOffsetY = r.f32();
  h.MRUOffsetX = r.f32();
  h.MRUOffsetZ = r.f32();
  h.MRUOffsetYaw = r.f32();
  h.MRUOffsetPitch = r.f32();
  h.MRUOffsetRoll = r.f32();
  for (auto& c : h.ChanInfo) c = XtfChanInfo::decode(r);
  return h;
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

// ---------------------------------------------------------------------------------------------
void XtfPacketHeader::encode(ByteWriter& w) const {
  w.u16(MagicNumber);
  w.u8(HeaderType);
  w.u8(SubChannelNumber);
  w.u16(NumChansToFollow);
  w.u16(Reserved1[0]);
  w.u16(Reserved1[1]);
  w.u32(NumBytesThisRecord);
}

XtfPacketHeader XtfPacketHeader::decode(ByteReader& r) {
  XtfPacketHeader h;
  h.MagicNumber = r.u16();
  h.HeaderType = r.u8();
  h.SubChannelNumber = r.u8();
  h.NumChansToFollow = r.u16();
  h.Reserved1[0] = r.u16();
  h.Reserved1[1] = r.u16();
  h.NumBytesThisRecord = r.u32();
  return h;
}

// ---------------------------------------------------------------------------------------------
void XtfPingHeader::encode(ByteWriter& w) const {
  Header.encode(w);
  w.u16(Year);
  w.u8(Month);
  w.u8(Day);
  w.u8(Hour);
  w.u8(Minute);
  w.u8(Second);
  w.u8(HSeconds);
  w.u16(JulianDay);
  w.u32(EventNumber);
  w.u32(PingNumber);
  w.f32(SoundVelocity);
  w.f32(OceanTide);
  w.u32(Reserved2);
  w.f32(ConductivityFreq);
  w.f32(TemperatureFreq);
  w.f32(PressureFreq);
  w.f32(PressureTemp);
  w.f32(Conductivity);
  w.f32(WaterTemperature);
  w.f32(Pressure);
  w.f32(ComputedSoundVelocity);
  w.f32(MagX);
  w.f32(MagY);
  w.f32(MagZ);
  w.f32(AuxVal1);
  w.f32(AuxVal2);
  w.f32(AuxVal3);
  w.f32(AuxVal4);
  w.f32(AuxVal5);
  w.f32(AuxVal6);
  w.f32(SpeedLog);
  w.f32(Turbidity);
  w.f32(ShipSpeed);
  w.f32(ShipGyro);
  w.f64(ShipYcoordinate);
  w.f64(ShipXcoordinate);
  w.u16(ShipAltitude);
  w.u16(ShipDepth);
  w.u8(FixTimeHour);
  w.u8(FixTimeMinute);
  w.u8(FixTimeSecond);
  w.u8(FixTimeHsecond);
  w.f32(SensorSpeed);
  w.f32(KP);
  w.f64(SensorYcoordinate);
  w.f64(SensorXcoordinate);
  w.u16(SonarStatus);
  w.u16(RangeToFish);
  w.u16(BearingToFish);
  w.u16(CableOut);
  w.f32(Layback);
  w.f32(CableTension);
  w.f32(SensorDepth);
  w.f32(SensorPrimaryAltitude);
  w.f32(SensorAuxAltitude);
  w.f32(SensorPitch);
  w.f32(SensorRoll);
  w.f32(SensorHeading);
  w.f32(Heave);
  w.f32(Yaw);
  w.u32(AttitudeTimeTag);
  w.f32(DOT);
  w.u32(NavFixMilliseconds);
  w.u8(ComputerClockHour);
  w.u8(ComputerClockMinute);
  w.u8(ComputerClockSecond);
  w.u8(ComputerClockHsec);
  w.i16(FishPositionDeltaX);
  w.i16(FishPositionDeltaY);
  w.u8(FishPositionErrorCode);
  w.u32(OptionalOffset);
  w.u8(CableOutHundredths);
  w.bytes(ReservedSpace2);
}

XtfPingHeader XtfPingHeader::decode(ByteReader& r) {
  XtfPingHeader h;
  h.Header = XtfPacketHeader::decode(r);
  h.Year = r.u16();
  h.Month = r.u8();
  h.Day = r.u8();
  h.Hour = r.u8();
  h.Minute = r.u8();
  h.Second = r.u8();
  h.HSeconds = r.u8();
  h.JulianDay = r.u16();
  h.EventNumber = r.u32();
  h.PingNumber = r.u32();
  h.SoundVelocity = r.f32();
  h.OceanTide = r.f32();
  h.Reserved2 = r.u32();
  h.ConductivityFreq = r.f32();
  h.TemperatureFreq = r.f32();
  h.PressureFreq = r.f32();
  h.PressureTemp = r.f32();
  h.Conductivity = r.f32();
  h.WaterTemperature = r.f32();
  h.Pressure = r.f32();
  h.ComputedSoundVelocity = r.f32();
  h.MagX = r.f32();
  h.MagY = r.f32();
  h.MagZ = r.f32();
  h.AuxVal1 = r.f32();
  h.AuxVal2 = r.f32();
  h.AuxVal3 = r.f32();
  h.AuxVal4 = r.f32();
  h.AuxVal5 = r.f32();
  h.AuxVal6 = r.f32();
  h.SpeedLog = r.f32();
  h.Turbidity = r.f32();
  h.ShipSpeed = r.f32();
  h.ShipGyro = r.f32();
  h.ShipYcoordinate = r.f64();
  h.ShipXcoordinate = r.f64();
  h.ShipAltitude = r.u16();
  h.ShipDepth = r.u16();
  h.FixTimeHour = r.u8();
  h.FixTimeMinute = r.u8();
  h.FixTimeSecond = r.u8();
  h.FixTimeHsecond = r.u8();
  h.SensorSpeed = r.f32();
  h.KP = r.f32();
  h.SensorYcoordinate = r.f64();
  h.SensorXcoordinate = r.f64();
  h.SonarStatus = r.u16();
  h.RangeToFish = r.u16();
  h.BearingToFish = r.u16();
  h.CableOut = r.u16();
  h.Layback = r.f32();
  h.CableTension = r.f32();
  h.SensorDepth = r.f32();
  h.SensorPrimaryAltitude = r.f32();
  h.SensorAuxAltitude = r.f32();
  h.SensorPitch = r.f32();
  h.SensorRoll = r.f32();
  h.SensorHeading = r.f32();
  h.Heave = r.f32();
  h.Yaw = r.f32();
  h.AttitudeTimeTag = r.u32();
  h.DOT = r.f32();
  h.NavFixMilliseconds = r.u32();
  h.ComputerClockHour = r.u8();
  h.ComputerClockMinute = r.u8();
  h.ComputerClockSecond = r.u8();
  h.ComputerClockHsec = r.u8();
  h.FishPositionDeltaX = r.i16();
  h.FishPositionDeltaY = r.i16();
  h.FishPositionErrorCode = r.u8();
  h.OptionalOffset = r.u32();
  h.CableOutHundredths = r.u8();
  r.bytes(h.ReservedSpace2);
  return h;
}

// ---------------------------------------------------------------------------------------------
void XtfPingChanHeader::encode(ByteWriter& w) const {
  w.u16(ChannelNumber);
  w.u16(DownsampleMethod);
  w.f32(SlantRange);
  w.f32(GroundRange);
  w.f32(TimeDelay);
  w.f32(TimeDuration);
  w.f32(SecondsPerPing);
  w.u16(ProcessingFlags);
  w.u16(Frequency);
  w.u16(InitialGainCode);
  w.u16(GainCode);
  w.u16(BandWidth);
  w.u32(ContactNumber);
  w.u16(ContactClassification);
  w.u8(ContactSubNumber);
  w.u8(ContactType);
  w.u32(NumSamples);
  w.u16(MillivoltScale);
  w.f32(ContactTimeOffTrack);
  w.u8(ContactCloseNumber);
  w.u8(Reserved2);
  w.f32(FixedVSOP);
  w.i16(Weight);
  w.bytes(ReservedSpace);
}

XtfPingChanHeader XtfPingChanHeader::decode(ByteReader& r) {
  XtfPingChanHeader h;
  h.ChannelNumber = r.u16();
  h.DownsampleMethod = r.u16();
  h.SlantRange = r.f32();
  h.GroundRange = r.f32();
  h.TimeDelay = r.f32();
  h.TimeDuration = r.f32();
  h.SecondsPerPing = r.f32();
  h.ProcessingFlags = r.u16();
  h.Frequency = r.u16();
  h.InitialGainCode = r.u16();
  h.GainCode = r.u16();
  h.BandWidth = r.u16();
  h.ContactNumber = r.u32();
  h.ContactClassification = r.u16();
  h.ContactSubNumber = r.u8();
  h.ContactType = r.u8();
  h.NumSamples = r.u32();
  h.MillivoltScale = r.u16();
  h.ContactTimeOffTrack = r.f32();
  h.ContactCloseNumber = r.u8();
  h.Reserved2 = r.u8();
  h.FixedVSOP = r.f32();
  h.Weight = r.i16();
  r.bytes(h.ReservedSpace);
  return h;
}

// ---------------------------------------------------------------------------------------------
void XtfNotesHeader::encode(ByteWriter& w) const {
  Header.encode(w);
  w.u16(Year);
  w.u8(Month);
  w.u8(Day);
  w.u8(Hour);
  w.u8(Minute);
  w.u8(Second);
  w.bytes(ReservedBytes);
  w.chars(NotesText);
}

XtfNotesHeader XtfNotesHeader::decode(ByteReader& r) {
  XtfNotesHeader h;
  h.Header = XtfPacketHeader::decode(r);
  h.Year = r.u16();
  h.Month = r.u8();
  h.Day = r.u8();
  h.Hour = r.u8();
  h.Minute = r.u8();
  h.Second = r.u8();
  r.bytes(h.ReservedBytes);
  r.chars(h.NotesText);
  return h;
}

// ---------------------------------------------------------------------------------------------
void XtfAttitudeData::encode(ByteWriter& w) const {
  Header.encode(w);
  w.u32(Reserved2[0]);
  w.u32(Reserved2[1]);
  w.u32(EpochMicroseconds);
  w.u32(SourceEpoch);
  w.f32(Pitch);
  w.f32(Roll);
  w.f32(Heave);
  w.f32(Yaw);
  w.u32(TimeTag);
  w.f32(Heading);
  w.u16(Year);
  w.u8(Month);
  w.u8(Day);
  w.u8(Hour);
  w.u8(Minutes);
  w.u8(Seconds);
  w.u16(Milliseconds);
  w.u8(Reserved3);
}

XtfAttitudeData XtfAttitudeData::decode(ByteReader& r) {
  XtfAttitudeData a;
  a.Header = XtfPacketHeader::decode(r);
  a.Reserved2[0] = r.u32();
  a.Reserved2[1] = r.u32();
  a.EpochMicroseconds = r.u32();
  a.SourceEpoch = r.u32();
  a.Pitch = r.f32();
  a.Roll = r.f32();
  a.Heave = r.f32();
  a.Yaw = r.f32();
  a.TimeTag = r.u32();
  a.Heading = r.f32();
  a.Year = r.u16();
  a.Month = r.u8();
  a.Day = r.u8();
  a.Hour = r.u8();
  a.Minutes = r.u8();
  a.Seconds = r.u8();
  a.Milliseconds = r.u16();
  a.Reserved3 = r.u8();
  return a;
}

// ---------------------------------------------------------------------------------------------
void XtfHeaderNavigation::encode(ByteWriter& w) const {
  w.u16(MagicNumber);
  w.u8(HeaderType);
  w.bytes(Reserved);
  w.u32(NumBytesThisRecord);
  w.u16(Year);
  w.u8(Month);
  w.u8(Day);
  w.u8(Hour);
  w.u8(Minute);
  w.u8(Second);
  w.u32(Microseconds);
  w.u32(SourceEpoch);
  w.u32(TimeTag);
  w.f64(RawYcoordinate);
  w.f64(RawXcoordinate);
  w.f64(RawAltitude);
  w.u8(TimeFlag);
  w.bytes(Reserved1);
}

XtfHeaderNavigation XtfHeaderNavigation::decode(ByteReader& r) {
  XtfHeaderNavigation n;
  n.MagicNumber = r.u16();
  n.HeaderType = r.u8();
  r.bytes(n.Reserved);
  n.NumBytesThisRecord = r.u32();
  n.Year = r.u16();
  n.Month = r.u8();
  n.Day = r.u8();
  n.Hour = r.u8();
  n.Minute = r.u8();
  n.Second = r.u8();
  n.Microseconds = r.u32();
  n.SourceEpoch = r.u32();
  n.TimeTag = r.u32();
  n.RawYcoordinate = r.f64();
  n.RawXcoordinate = r.f64();
  n.RawAltitude = r.f64();
  n.TimeFlag = r.u8();
  r.bytes(n.Reserved1);
  return n;
}

}  // namespace sonarsynth::xtf
