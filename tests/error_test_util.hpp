// SPDX-License-Identifier: MIT
// The messages of the errors the tests provoke.
#pragma once

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>
#include <string_view>

#include "sonarsynth/error.hpp"

namespace sonarsynth::test {

/// The message of the E that `f` throws; "(no exception of the expected type)" if it throws none.
template <class E = InputError, class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "(no exception of the expected type)";
}

/// Expects `f` to throw an E whose message holds every one of `fragments`; `what` names the
/// input in the failure when nothing is thrown.
template <class E = InputError, class F>
void expect_error(F&& f, std::initializer_list<std::string_view> fragments,
                  const std::string& what) {
  try {
    f();
    ADD_FAILURE() << "no error for:\n" << what;
  } catch (const E& e) {
    for (const std::string_view fragment : fragments) {
      EXPECT_NE(std::string_view(e.what()).find(fragment), std::string_view::npos)
          << "'" << fragment << "' not in: " << e.what();
    }
  }
}

}  // namespace sonarsynth::test
