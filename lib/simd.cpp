// SPDX-License-Identifier: MIT
// Run-time choice of the vector kernels' instruction set (Highway's dynamic dispatch).
// Every kernel file compiles itself once per target with hwy/foreach_target.h and calls
// HWY_DYNAMIC_DISPATCH, which picks among hwy::SupportedTargets(); set_target narrows that set.
#include "sonarsynth/simd.hpp"

#include <cstdint>
#include <cstdlib>
#include <mutex>
#include <string>
#include <vector>

#include "sonarsynth/enum_names.hpp"
#include "sonarsynth/error.hpp"

// clang-format off
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "lib/simd.cpp"
#include <hwy/foreach_target.h>
#include <hwy/highway.h>
// clang-format on

HWY_BEFORE_NAMESPACE();
namespace sonarsynth::simd::HWY_NAMESPACE {
// The target this copy of the code was compiled for.
std::int64_t compiled_target() {
  return HWY_TARGET;
}
}  // namespace sonarsynth::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace sonarsynth::simd {

HWY_EXPORT(compiled_target);

namespace {

// The Highway targets a cap allows (each cap also allows every target below it).
std::int64_t allowed_mask(Target t) {
  switch (t) {
    case Target::avx512:
      return HWY_AVX3 | HWY_AVX2 | HWY_EMU128 | HWY_SCALAR;
    case Target::avx2:
      return HWY_AVX2 | HWY_EMU128 | HWY_SCALAR;
    case Target::scalar:
      return HWY_EMU128 | HWY_SCALAR;
    case Target::automatic:
      break;
  }
  return ~std::int64_t{0};
}

// The Highway target a cap names (the one that must be supported for the cap to be usable).
std::int64_t named_target(Target t) {
  switch (t) {
    case Target::avx512:
      return HWY_AVX3;
    case Target::avx2:
      return HWY_AVX2;
    case Target::scalar:
      return HWY_EMU128 | HWY_SCALAR;
    case Target::automatic:
      break;
  }
  return 0;
}

std::int64_t hardware_targets() {
  // Read before any cap is set (set_target asks supported() first).
  static const std::int64_t all = hwy::SupportedTargets();
  return all;
}

constexpr EnumName<Target> kTargetNames[] = {{Target::automatic, "auto"},
                                             {Target::avx512, "avx512"},
                                             {Target::avx2, "avx2"},
                                             {Target::scalar, "scalar"}};

}  // namespace

Target parse_target(std::string_view name, std::string_view what) {
  return parse_enum(kTargetNames, name, what);
}

std::string_view target_name(Target t) {
  return enum_name(kTargetNames, t);
}

bool supported(Target t) {
  if (t == Target::automatic || t == Target::scalar) return true;
  return (hardware_targets() & HWY_TARGETS & named_target(t)) != 0;
}

std::vector<Target> supported_targets() {
  std::vector<Target> out;
  for (const Target t : {Target::scalar, Target::avx2, Target::avx512}) {
    if (supported(t)) out.push_back(t);
  }
  return out;
}

void set_target(Target t) {
  if (!supported(t)) {
    throw InputError("SIMD target '" + std::string(target_name(t)) +
                     "' is not supported by this CPU or build");
  }
  const std::int64_t hw = hardware_targets();
  // A mock of 0 restores the CPU's own set; otherwise the set is the CPU's, capped.
  hwy::SetSupportedTargetsForTest(t == Target::automatic ? 0 : (hw & allowed_mask(t)));
}

Target active_target() {
  const std::int64_t chosen = HWY_DYNAMIC_DISPATCH(compiled_target)();
  if (chosen == HWY_AVX3) return Target::avx512;
  if (chosen == HWY_AVX2) return Target::avx2;
  return Target::scalar;
}

void configure_from_environment() {
  static std::once_flag once;
  std::call_once(once, [] {
    const char* v = std::getenv("SONARSYNTH_SIMD");
    if (v != nullptr && *v != '\0') set_target(parse_target(v, "environment SONARSYNTH_SIMD"));
  });
}

}  // namespace sonarsynth::simd
#endif  // HWY_ONCE
