// SPDX-License-Identifier: MIT
// Helpers of the formats' `info` summaries (formats/xtf/info.cpp, formats/jsf/info.cpp).
#pragma once

#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "sonarsynth/formats/xtf/summary.hpp"

namespace sonarsynth::info {

using Json = nlohmann::ordered_json;  // keys in the order written

inline Json json_range(const xtf::ValueRange& r) {
  if (r.count == 0) return nullptr;
  return {{"min", r.min}, {"max", r.max}};
}

/// Text from a file (any bytes) as JSON: each byte one character (ISO 8859-1), so that every
/// byte is kept and the output is valid UTF-8 (printed as \u00XX escapes: ASCII output).
inline std::string file_text(const std::string& bytes) {
  std::string out;
  for (const char ch : bytes) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x80) {
      out += ch;
    } else {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  return out;
}

inline std::string text_range(const xtf::ValueRange& r, int precision = 3) {
  if (r.count == 0) return "(none)";
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(precision);
  os << r.min << " .. " << r.max;
  return os.str();
}

}  // namespace sonarsynth::info
