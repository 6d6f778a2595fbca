// SPDX-License-Identifier: MIT
#pragma once

// Private helpers: UtcTime <-> the broken-down calendar fields XTF and JSF records store.

#include <chrono>
#include <cstdint>
#include <optional>

#include "sonarsynth/formats/io/sonar_ping.hpp"

namespace sonarsynth::calendar {

struct TimeFields {
  int year = 1970;
  unsigned month = 1;
  unsigned day = 1;
  unsigned hour = 0;
  unsigned minute = 0;
  unsigned second = 0;
  std::uint32_t microsecond = 0;  ///< 0..999999
  unsigned day_of_year0 = 0;      ///< 0-based day of the year (XTF JulianDay as written by Isis)
};

inline TimeFields fields_from_time(UtcTime t) {
  using namespace std::chrono;
  const auto day = floor<days>(t);
  const year_month_day ymd{day};
  const auto since_midnight = t - day;
  const hh_mm_ss<microseconds> hms{since_midnight};
  TimeFields f;
  f.year = static_cast<int>(ymd.year());
  f.month = static_cast<unsigned>(ymd.month());
  f.day = static_cast<unsigned>(ymd.day());
  f.hour = static_cast<unsigned>(hms.hours().count());
  f.minute = static_cast<unsigned>(hms.minutes().count());
  f.second = static_cast<unsigned>(hms.seconds().count());
  f.microsecond = static_cast<std::uint32_t>(hms.subseconds().count());
  const sys_days jan1{ymd.year() / January / 1};
  f.day_of_year0 = static_cast<unsigned>((day - jan1).count());
  return f;
}

/// The time of valid calendar fields; nullopt if any field is out of range (month 13, day 31 of
/// a 30-day month, hour 24, microsecond >= 1e6, a year outside 1..9999, which ISO 8601 text
/// and std::chrono::year cannot hold: 65535 would wrap to -1). Seconds may be 60 (leap second,
/// folded).
inline std::optional<UtcTime> time_from_fields(int year, unsigned month, unsigned day,
                                               unsigned hour, unsigned minute, unsigned second,
                                               std::uint32_t microsecond) {
  using namespace std::chrono;
  if (year < 1 || year > 9999) return std::nullopt;
  const year_month_day ymd{std::chrono::year{year}, std::chrono::month{month},
                           std::chrono::day{day}};
  if (!ymd.ok() || hour > 23 || minute > 59 || second > 60 || microsecond > 999999) {
    return std::nullopt;
  }
  return sys_days{ymd} + hours{hour} + minutes{minute} + seconds{second} +
         microseconds{microsecond};
}

/// Seconds since 1970-01-01 (UTC) of `t`, for SourceEpoch fields (floor).
inline std::int64_t epoch_seconds(UtcTime t) {
  return std::chrono::floor<std::chrono::seconds>(t).time_since_epoch().count();
}

/// A 32-bit millisecond time tag shared by ping AttitudeTimeTag and attitude TimeTag:
/// milliseconds since 1970 modulo 2^32.
inline std::uint32_t time_tag_ms(UtcTime t) {
  const auto ms = std::chrono::floor<std::chrono::milliseconds>(t).time_since_epoch().count();
  return static_cast<std::uint32_t>(static_cast<std::uint64_t>(ms) & 0xFFFFFFFFu);
}

}  // namespace sonarsynth::calendar
