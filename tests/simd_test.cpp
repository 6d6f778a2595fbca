// SPDX-License-Identifier: MIT
// The run-time choice of the vector kernels' instruction set (lib/simd.cpp).
#include "sonarsynth/simd.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "sonarsynth/error.hpp"

namespace {

using sonarsynth::simd::Target;
namespace simd = sonarsynth::simd;

TEST(Simd, NamesRoundTripAndBadNamesAreRefused) {
  for (const Target t : {Target::automatic, Target::avx512, Target::avx2, Target::scalar}) {
    EXPECT_EQ(simd::parse_target(simd::target_name(t)), t);
  }
  try {
    simd::parse_target("sse9", "--simd");
    FAIL() << "sse9 accepted";
  } catch (const sonarsynth::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--simd = 'sse9'"), std::string::npos) << e.what();
  }
}

// Each cap the CPU supports is the target the kernels then dispatch to; a cap is undone by auto.
TEST(Simd, CapsChooseTheDispatchedTarget) {
  simd::set_target(Target::automatic);  // undo a SONARSYNTH_SIMD applied by other tests' kernels
  const Target best = simd::active_target();
  EXPECT_NE(best, Target::automatic);
  for (const Target t : {Target::scalar, Target::avx2, Target::avx512}) {
    if (!simd::supported(t)) {
      EXPECT_THROW(simd::set_target(t), sonarsynth::InputError);
      continue;
    }
    simd::set_target(t);
    EXPECT_EQ(simd::active_target(), t);
  }
  simd::set_target(Target::automatic);
  EXPECT_EQ(simd::active_target(), best);
  const std::vector<Target> all = simd::supported_targets();
  ASSERT_FALSE(all.empty());
  EXPECT_EQ(all.front(), Target::scalar);
  for (const Target t : all) EXPECT_TRUE(simd::supported(t));
}

}  // namespace
