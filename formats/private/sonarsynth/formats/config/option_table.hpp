// SPDX-License-Identifier: MIT
// Internal to sonarsynth::formats: every scalar option of a scene file's simulation sections,
// declared once (key path, unit, bounds, command-line flag, the struct field it fills). The
// YAML reader, the command-line overrides and effective.yaml all go through this table; an
// option left out of the file keeps the struct's default (docs/scene-format.md).
#pragma once

#include <yaml-cpp/yaml.h>

#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "sonarsynth/formats/config/simulation_file.hpp"
#include "sonarsynth/formats/config/yaml_fields.hpp"

namespace sonarsynth::options {

/// A command-line flag of `simulate` that overrides options of the table, declared here once:
/// the CLI's options, the override checks and effective.yaml derive from it (override_flags(),
/// set_override()).
struct Flag {
  std::string_view name;  ///< "--range"
  std::string_view help;  ///< the CLI's help line
  /// Whether the overrides give it.
  bool (*given)(const SimulationOverrides&) = nullptr;
  /// Sets it from its command-line text; throws InputError naming the flag (`name`), the text
  /// and the values allowed.
  void (*parse)(SimulationOverrides&, const std::string& text, std::string_view name) = nullptr;
};

/// The flags of the table's rows, each once, in declaration order.
const std::vector<const Flag*>& flags();

enum class Kind {
  real,     ///< a finite number (in `unit`), converted into the struct's unit by `set`
  integer,  ///< a number taken as an integer (a count)
  boolean,  ///< true or false
  choice,   ///< one of `choices` (the value is its index)
  seed,     ///< an unsigned 64-bit integer: the top-level seed
};

struct Option {
  std::string_view section;  ///< "sonar", "render.water", "" at the top level
  std::string_view key;      ///< "range_m"
  std::string_view unit;     ///< unit in the file: "m", "deg", "kHz", "us", "dB", "" ...
  Kind kind = Kind::real;
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;        ///< lo < v rather than lo <= v
  const Flag* flag = nullptr;  ///< the command-line flag that overrides it, if any
  std::string_view word;       ///< real/integer: a word accepted instead of a number ("auto")
  std::vector<std::string_view> choices;  ///< choice: the names, by value
  std::string_view choice_constraint;     ///< choice: "paper or lambert"
  /// The value in file units (choice: index; `word`: NaN; boolean: 0 or 1). Seeds: use seed_of.
  double (*get)(const SimulationSetup&) = nullptr;
  void (*set)(SimulationSetup&, double) = nullptr;

  std::string path() const;  ///< "sonar.range_m"
  /// The bounds as a scene file states them: "range_m > 0 and <= 100000".
  std::string constraint() const;
  /// The bounds without the key: "> 0 and <= 100000".
  std::string bounds() const;
  bool accepts(double v) const;
};

/// Every declared option, in the order of docs/scene-format.md.
const std::vector<Option>& all();
/// The options of one section (e.g. "render.quality"), in declaration order.
std::vector<const Option*> in_section(std::string_view section);
/// The option at a key path ("sonar.range_m"); throws std::out_of_range if none.
const Option& at(std::string_view path);

std::uint64_t seed_of(const SimulationSetup& s);

/// Reads `o` from the map `f` (its section) into `s` if the key is given; otherwise leaves the
/// struct's default. Throws InputError naming the file, key path and value.
void read(const yaml::Fields& f, const Option& o, SimulationSetup& s);
/// Reads every declared option of `section` (the section `f` is) in declaration order.
void read_all(const yaml::Fields& f, std::string_view section, SimulationSetup& s);

/// The value of `o` in `s` as effective.yaml writes it.
YAML::Node emit(const Option& o, const SimulationSetup& s);

}  // namespace sonarsynth::options
