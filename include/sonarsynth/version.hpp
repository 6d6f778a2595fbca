// SPDX-License-Identifier: MIT
#pragma once

namespace sonarsynth {
inline constexpr const char* kVersion = "0.1.0";
}  // namespace sonarsynth
