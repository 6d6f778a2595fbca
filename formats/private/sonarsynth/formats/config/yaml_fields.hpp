// SPDX-License-Identifier: MIT
// Internal to sonarsynth::formats: typed access to YAML nodes with errors that name the file,
// the key path and the bad value ("scene.yaml: objects[2].diameter_m = -1. Violated ...").
#pragma once

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sonarsynth/error.hpp"

namespace sonarsynth {
struct LabelOutput;  // include/sonarsynth/formats/config/simulation_file.hpp
}

namespace sonarsynth::yaml {

class Fields {
 public:
  Fields(YAML::Node node, std::string file, std::string path)
      : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {}

  const YAML::Node& node() const { return node_; }
  const std::string& file() const { return file_; }
  /// "a.b" key path of this node ("" at the document root).
  const std::string& path() const { return path_; }
  std::string key_path(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
  }

  bool has(const std::string& key) const {
    return node_.IsMap() && node_[key].IsDefined() && !node_[key].IsNull();
  }
  Fields child(const std::string& key) const;
  /// Elements of a sequence under `key` (empty if absent); throws if it is not a sequence.
  std::vector<Fields> sequence(const std::string& key) const;

  [[noreturn]] void fail(const std::string& key, const std::string& msg) const;
  [[noreturn]] void fail_value(const std::string& key, const std::string& constraint) const;

  double number(const std::string& key) const;
  /// True if `key` is given; throws naming it if it is given as null (a null is not taken as
  /// "use the default": leave the key out for that).
  bool given(const std::string& key) const;
  double number(const std::string& key, double fallback) const {
    return given(key) ? number(key) : fallback;
  }
  /// A number that must satisfy lo <= v <= hi (inclusive), or lo < v when `lo_exclusive`.
  double number_in(const std::string& key, double fallback, double lo, double hi,
                   bool lo_exclusive = false) const;
  std::int64_t integer(const std::string& key, std::int64_t fallback) const;
  std::uint64_t seed(const std::string& key, std::uint64_t fallback) const;
  bool boolean(const std::string& key, bool fallback) const;
  std::string text(const std::string& key) const;
  std::string text(const std::string& key, const std::string& fallback) const {
    return given(key) ? text(key) : fallback;
  }
  /// A fixed-length list of numbers, e.g. size_m: [480, 0.5, 0.5].
  std::vector<double> numbers(const std::string& key, std::size_t count) const;
  /// The number in `element` (an item of the list under `key`, at `index`): throws naming
  /// "key[index]" and the value unless it is a finite number.
  double element_number(const std::string& key, const YAML::Node& element, std::size_t index) const;
  /// The string in the scalar `value` found under `key`; throws naming it otherwise.
  std::string scalar_text(const std::string& key, const YAML::Node& value) const;
  /// Throws naming the first key of this map that is not in `allowed` (catches typos), or
  /// that is not a plain scalar (a YAML complex key such as `? [a, b]`).
  void only(const std::set<std::string>& allowed) const;

 private:
  YAML::Node node_;
  std::string file_;
  std::string path_;
};

/// An `output.labels` block (docs/labels.md) read as the scene reader reads it (the same keys,
/// bounds and messages), wherever it appears: a scene file's output.labels, a dataset spec's
/// run.products.labels. `truth`: whether the run writes truth (labels need it). Defined in
/// formats/config/simulation_file.cpp.
LabelOutput read_label_output(const Fields& f, bool truth);

/// `file` relative to `base_dir` unless absolute, normalised.
std::string resolve_path(const std::filesystem::path& base_dir, const std::string& file);

/// Runs `load` (which reads a YAML document of `file`), turning a YAML::Exception that escapes
/// from it (a value yaml-cpp cannot convert, e.g. a list where a number is expected) into an
/// InputError naming the file, the line and the column.
template <class F>
auto with_file_errors(const std::string& file, F&& load) -> decltype(load()) {
  try {
    return load();
  } catch (const YAML::Exception& e) {
    const std::string where = e.mark.is_null()
                                  ? ""
                                  : " at line " + std::to_string(e.mark.line + 1) + ", column " +
                                        std::to_string(e.mark.column + 1);
    throw InputError(file + ": value" + where + " has the wrong type (" + e.msg + ")");
  }
}

/// Loads a YAML file; throws FormatError naming the file (and line) when it is malformed.
YAML::Node load_file(const std::string& path);
/// Parses YAML text; throws FormatError naming `name` (and line) when it is malformed.
YAML::Node load_string(const std::string& text, const std::string& name);

}  // namespace sonarsynth::yaml
