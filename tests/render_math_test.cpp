// SPDX-License-Identifier: MIT
// The renderer's scalar math (sonarsynth/render_math.hpp) against the standard library and a
// long double reference.
#include "sonarsynth/render_math.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

namespace sonarsynth {
namespace {

TEST(RenderMath, FloorFastIsStdFloor) {
  // Bit for bit, at the cases that matter: integers and their neighbours of both signs, halves,
  // zeros, the 2^52 boundary, huge values, infinities and NaN.
  std::vector<double> xs = {0.0,
                            -0.0,
                            0.5,
                            -0.5,
                            1.0,
                            -1.0,
                            0x1p52,
                            -0x1p52,
                            0x1p60,
                            -0x1p60,
                            1e300,
                            -1e300,
                            std::numeric_limits<double>::infinity(),
                            -std::numeric_limits<double>::infinity(),
                            std::numeric_limits<double>::denorm_min()};
  for (double b : {0.0, 1.0, 7.0, 4503599627370495.0, 123456.0}) {
    for (double s : {1.0, -1.0}) {
      xs.push_back(s * b);
      xs.push_back(std::nextafter(s * b, 1e308));
      xs.push_back(std::nextafter(s * b, -1e308));
      xs.push_back(s * b + 0.5);
    }
  }
  for (int k = 0; k < 10000; ++k) xs.push_back((k - 5000) * 0.37 + 1e-3 * k);
  for (const double x : xs) {
    const double got = render_math::floor_fast(x), want = std::floor(x);
    ASSERT_EQ(std::signbit(got), std::signbit(want)) << x;
    ASSERT_EQ(got, want) << x;
  }
  EXPECT_TRUE(std::isnan(render_math::floor_fast(std::nan(""))));
}

TEST(RenderMath, CosHalfPiAgainstALongDoubleReference) {
  // The reference: sin(pi/2 (1 - |x|)) in x87 extended precision (64-bit mantissa), which is
  // cos(pi/2 x) without the cancellation near the zeros at |x| = 1 that a double cos() of a
  // rounded argument has. Dense in [-1, 1], plus the ends and the zero.
  const long double half_pi = 1.5707963267948966192313216916397514L;
  double worst = 0.0;
  auto check = [&](double x) {
    const long double want = std::sin(half_pi * (1.0L - std::fabs(static_cast<long double>(x))));
    const double got = render_math::cos_half_pi(x);
    if (want == 0.0L) {
      ASSERT_EQ(got, 0.0) << x;
      return;
    }
    const double rel = static_cast<double>(std::fabs((got - want) / want));
    worst = std::max(worst, rel);
    ASSERT_LE(rel, 4e-16) << "x = " << x << ": " << got << " against " << static_cast<double>(want);
  };
  for (int k = -1'000'000; k <= 1'000'000; ++k) check(k * 1e-6);
  for (double x : {1.0, -1.0, std::nextafter(1.0, 0.0), std::nextafter(-1.0, 0.0), 1e-300, 0.5,
                   -0.5, 0.0, -0.0}) {
    check(x);
  }
  // Against the library cos where it is well conditioned (|x| <= 1/2).
  for (int k = -500; k <= 500; ++k) {
    const double x = k * 1e-3;
    EXPECT_NEAR(render_math::cos_half_pi(x), std::cos(0.5 * std::numbers::pi * x), 3e-16) << x;
  }
  EXPECT_GT(worst, 0.0);  // the comparison saw rounding, not a copy of the reference
  EXPECT_TRUE(std::isnan(render_math::cos_half_pi(std::nan(""))));
}

}  // namespace
}  // namespace sonarsynth
