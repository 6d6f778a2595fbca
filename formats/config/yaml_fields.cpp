// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/config/yaml_fields.hpp"

#include <cstdint>
#include <filesystem>
#include <map>
#include <sstream>

namespace sonarsynth::yaml {

namespace {
std::string value_text(const YAML::Node& n) {
  if (!n.IsDefined() || n.IsNull()) return "null";
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  std::ostringstream os;
  os << YAML::Dump(n);
  std::string s = os.str();
  for (char& c : s) {
    if (c == '\n') c = ' ';
  }
  return s.size() > 60 ? s.substr(0, 57) + "..." : s;
}
}  // namespace

void Fields::fail(const std::string& key, const std::string& msg) const {
  const std::string where = key.empty() ? path_ : key_path(key);
  throw InputError(file_ + ": " + (where.empty() ? "" : where + ": ") + msg);
}

void Fields::fail_value(const std::string& key, const std::string& constraint) const {
  throw InputError(file_ + ": " + key_path(key) + " = " + value_text(node_[key]) +
                   ". Violated constraint: " + constraint);
}

double Fields::element_number(const std::string& key, const YAML::Node& element,
                              std::size_t index) const {
  double v = 0;
  if (!element.IsScalar() || !YAML::convert<double>::decode(element, v) || !std::isfinite(v)) {
    throw InputError(file_ + ": " + key_path(key) + "[" + std::to_string(index) +
                     "] = " + value_text(element) + ". Violated constraint: a finite number");
  }
  return v;
}

std::string Fields::scalar_text(const std::string& key, const YAML::Node& value) const {
  if (!value.IsScalar()) {
    throw InputError(file_ + ": " + key_path(key) + " = " + value_text(value) +
                     ". Violated constraint: a string");
  }
  return value.Scalar();
}

bool Fields::given(const std::string& key) const {
  if (!node_.IsMap() || !node_[key].IsDefined()) return false;
  if (node_[key].IsNull()) {
    fail_value(key, "a value (leave " + key + " out for its default; null is not one)");
  }
  return true;
}

Fields Fields::child(const std::string& key) const {
  if (!has(key)) fail(key, "missing");
  if (!node_[key].IsMap()) fail_value(key, "a map of keys");
  return Fields(node_[key], file_, key_path(key));
}

std::vector<Fields> Fields::sequence(const std::string& key) const {
  std::vector<Fields> out;
  if (!has(key)) return out;
  const YAML::Node seq = node_[key];
  if (!seq.IsSequence()) fail_value(key, "a list");
  for (std::size_t i = 0; i < seq.size(); ++i) {
    out.emplace_back(seq[i], file_, key_path(key) + "[" + std::to_string(i) + "]");
  }
  return out;
}

double Fields::number(const std::string& key) const {
  if (!has(key)) fail(key, "missing (a number is required)");
  double v = 0;
  if (!node_[key].IsScalar() || !YAML::convert<double>::decode(node_[key], v) ||
      !std::isfinite(v)) {
    fail_value(key, "a finite number");
  }
  return v;
}

double Fields::number_in(const std::string& key, double fallback, double lo, double hi,
                         bool lo_exclusive) const {
  const double v = number(key, fallback);
  if ((lo_exclusive ? !(v > lo) : !(v >= lo)) || !(v <= hi)) {
    std::ostringstream c;
    c << (lo_exclusive ? "> " : ">= ") << lo;
    if (std::isfinite(hi)) c << " and <= " << hi;
    fail_value(key, key + " " + c.str());
  }
  return v;
}

std::int64_t Fields::integer(const std::string& key, std::int64_t fallback) const {
  if (!given(key)) return fallback;
  std::int64_t v = 0;
  if (!node_[key].IsScalar() || !YAML::convert<std::int64_t>::decode(node_[key], v)) {
    fail_value(key, "an integer");
  }
  return v;
}

std::uint64_t Fields::seed(const std::string& key, std::uint64_t fallback) const {
  if (!given(key)) return fallback;
  std::uint64_t v = 0;
  if (!node_[key].IsScalar() || !YAML::convert<std::uint64_t>::decode(node_[key], v)) {
    fail_value(key, "a non-negative integer");
  }
  return v;
}

bool Fields::boolean(const std::string& key, bool fallback) const {
  if (!given(key)) return fallback;
  bool v = false;
  if (!node_[key].IsScalar() || !YAML::convert<bool>::decode(node_[key], v)) {
    fail_value(key, "true or false");
  }
  return v;
}

std::string Fields::text(const std::string& key) const {
  if (!has(key)) fail(key, "missing (a string is required)");
  if (!node_[key].IsScalar()) fail_value(key, "a string");
  return node_[key].Scalar();
}

std::vector<double> Fields::numbers(const std::string& key, std::size_t count) const {
  if (!has(key)) fail(key, "missing (a list of " + std::to_string(count) + " numbers is required)");
  const YAML::Node seq = node_[key];
  std::vector<double> out;
  if (seq.IsSequence() && seq.size() == count) {
    for (std::size_t i = 0; i < count; ++i) {
      double v = 0;
      if (!seq[i].IsScalar() || !YAML::convert<double>::decode(seq[i], v) || !std::isfinite(v))
        break;
      out.push_back(v);
    }
  }
  if (out.size() != count) fail_value(key, "a list of " + std::to_string(count) + " numbers");
  return out;
}

void Fields::only(const std::set<std::string>& allowed) const {
  if (!node_.IsMap()) fail("", "expected a map of keys");
  std::set<std::string> seen;
  for (const auto& kv : node_) {
    if (!kv.first.IsScalar()) {
      fail("", "key " + value_text(kv.first) + " (line " +
                   std::to_string(kv.first.Mark().line + 1) +
                   ") is not a plain name (complex YAML keys are not supported)");
    }
    const std::string k = kv.first.Scalar();
    // YAML forbids duplicate keys but yaml-cpp keeps the first silently: the second would be
    // ignored without a word.
    if (!seen.insert(k).second) {
      fail(k, "duplicate key (line " + std::to_string(kv.first.Mark().line + 1) + ")");
    }
    if (!allowed.count(k)) {
      std::string known;
      for (const auto& a : allowed) known += (known.empty() ? "" : ", ") + a;
      fail(k, "unknown key (known here: " + known + ")");
    }
  }
}

std::string resolve_path(const std::filesystem::path& base_dir, const std::string& file) {
  const std::filesystem::path p(file);
  return (p.is_absolute() ? p : base_dir / p).lexically_normal().string();
}

namespace {
// Nodes of `n` counted as readers see them, every alias expanded; memoised per node (an alias is
// the anchored node itself, at the anchor's position), so the count costs one visit per node
// written in the file. Stops early past `cap`.
std::uint64_t expanded_nodes(const YAML::Node& n, std::map<std::size_t, std::uint64_t>& memo,
                             std::uint64_t cap) {
  if (!n.IsMap() && !n.IsSequence()) return 1;
  const std::size_t key = n.Mark().pos;
  if (const auto it = memo.find(key); it != memo.end()) return it->second;
  std::uint64_t count = 1;
  for (const auto& kv : n) {
    if (count > cap) break;
    if (n.IsMap()) {
      count += expanded_nodes(kv.first, memo, cap) + expanded_nodes(kv.second, memo, cap);
    } else {
      count += expanded_nodes(kv, memo, cap);
    }
  }
  memo[key] = count;
  return count;
}
}  // namespace

namespace {
// Aliases nested in aliases multiply: a few lines can stand for 10^9 nodes, which every
// traversal of the document would then visit.
void check_expansion(const YAML::Node& root, const std::string& name) {
  constexpr std::uint64_t kMaxNodes = 1'000'000;
  std::map<std::size_t, std::uint64_t> memo;
  if (expanded_nodes(root, memo, kMaxNodes) > kMaxNodes) {
    throw FormatError(name + ": the document expands to more than " + std::to_string(kMaxNodes) +
                      " nodes through aliases (*name). Violated constraint: at most " +
                      std::to_string(kMaxNodes) + " nodes once aliases are expanded");
  }
}

template <class F>
YAML::Node parse(const std::string& name, F&& load) {
  try {
    YAML::Node root = load();
    check_expansion(root, name);
    return root;
  } catch (const YAML::Exception& e) {
    throw FormatError(name + ": malformed YAML at line " + std::to_string(e.mark.line + 1) +
                      ", column " + std::to_string(e.mark.column + 1) + ": " + e.msg);
  }
}
}  // namespace

YAML::Node load_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw FormatError(
        path + (std::filesystem::exists(path, ec) ? ": not a regular file" : ": no such file"));
  }
  return parse(path, [&] { return YAML::LoadFile(path); });
}

YAML::Node load_string(const std::string& text, const std::string& name) {
  return parse(name, [&] { return YAML::Load(text); });
}

}  // namespace sonarsynth::yaml
