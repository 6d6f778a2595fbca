// SPDX-License-Identifier: MIT
// A time as the text of the configuration and products: ISO 8601 in UTC with microseconds,
// "2026-03-01T10:00:00.000000Z" (effective.yaml, the truth products' ping times).
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

#include "sonarsynth/formats/io/sonar_ping.hpp"

namespace sonarsynth::calendar {

inline std::string utc_text(UtcTime t) {
  const auto days = std::chrono::floor<std::chrono::days>(t);
  const std::chrono::year_month_day ymd{days};
  const auto us = (t - days).count();
  char buf[64];
  std::snprintf(buf, sizeof buf, "%04d-%02u-%02uT%02lld:%02lld:%09.6fZ",
                static_cast<int>(ymd.year()), static_cast<unsigned>(ymd.month()),
                static_cast<unsigned>(ymd.day()), static_cast<long long>(us / 3600000000LL),
                static_cast<long long>(us / 60000000LL % 60),
                static_cast<double>(us % 60000000LL) / 1e6);
  return buf;
}

}  // namespace sonarsynth::calendar
