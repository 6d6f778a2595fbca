// SPDX-License-Identifier: MIT
// Two structs compared member by member, for the tests that check a round trip or a default
// field by field.
#pragma once

#include <gtest/gtest.h>

#include <cmath>

namespace sonarsynth::test {

/// Expects `a.*m == b.*m` (EXPECT_EQ) for each member `m` listed, naming the member by its place
/// in the list on failure.
template <class S, class... T>
void expect_equal_fields(const S& a, const S& b, T S::*... members) {
  int place = 0;
  const auto expect = [&place](const auto& u, const auto& w) {
    EXPECT_EQ(u, w) << "member " << place;
    ++place;
  };
  (expect(a.*members, b.*members), ...);
}

/// As expect_equal_fields for floating-point members whose NaN is a value ("auto", "off"): a NaN
/// equals a NaN.
template <class S, class... T>
void expect_same_fields(const S& a, const S& b, T S::*... members) {
  int place = 0;
  const auto expect = [&place](double u, double w) {
    EXPECT_TRUE(u == w || (std::isnan(u) && std::isnan(w)))
        << "member " << place << ": " << u << " vs " << w;
    ++place;
  };
  (expect(a.*members, b.*members), ...);
}

}  // namespace sonarsynth::test
