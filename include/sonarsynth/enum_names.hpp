// SPDX-License-Identifier: MIT
#pragma once

// An option enum's names, listed once in a table that both directions use:
//
//   constexpr EnumName<MosaicRule> kRuleNames[] = {{MosaicRule::weighted_mean, "mean"}, ...};
//   parse_enum(kRuleNames, "max", "--rule");  // MosaicRule::max
//   enum_name(kRuleNames, MosaicRule::max);   // "max"

#include <cstddef>
#include <string>
#include <string_view>

#include "sonarsynth/error.hpp"

namespace sonarsynth {

template <class E>
struct EnumName {
  E value;
  const char* name;
};

/// The value named `text`. Throws InputError naming `what`, the text and the table's names
/// ("--rule = 'median'. Violated constraint: one of mean, max, nearest").
template <class E, std::size_t N>
E parse_enum(const EnumName<E> (&names)[N], std::string_view text, std::string_view what) {
  std::string allowed;
  for (const EnumName<E>& n : names) {
    if (text == n.name) return n.value;
    allowed += (allowed.empty() ? "" : ", ") + std::string(n.name);
  }
  throw InputError(std::string(what) + " = '" + std::string(text) +
                   "'. Violated constraint: one of " + allowed);
}

/// The name of `value`; "?" for a value the table does not list.
template <class E, std::size_t N>
const char* enum_name(const EnumName<E> (&names)[N], E value) {
  for (const EnumName<E>& n : names) {
    if (n.value == value) return n.name;
  }
  return "?";
}

}  // namespace sonarsynth
