// SPDX-License-Identifier: MIT
#pragma once

#include <string>

namespace sonarsynth::json {

/// A JSON string literal of `s`, ASCII only (control and non-ASCII bytes as \u00XX: strings from
/// files may be any bytes).
std::string string_literal(const std::string& s);
/// A JSON number with 10 significant digits, or null for NaN/infinity.
std::string number(double v);

}  // namespace sonarsynth::json
