// SPDX-License-Identifier: MIT
// Dataset specs (docs/dataset.md): reading and validating the spec file, and drawing item k's
// scene file from it with counter-based random numbers keyed by the item's seed.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "sonarsynth/formats/config/mesh_file.hpp"
#include "sonarsynth/formats/config/option_table.hpp"
#include "sonarsynth/bathy_gen.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/bathy_spec_parser.hpp"
#include "sonarsynth/formats/config/dataset.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"  // RunLimits
#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/material.hpp"
#include "sonarsynth/object_types.hpp"
#include "sonarsynth/sonar_presets.hpp"
#include "sonarsynth/formats/config/yaml_fields.hpp"

namespace sonarsynth {
namespace {

using yaml::Fields;

constexpr double kInf = std::numeric_limits<double>::infinity();
// Salt of the item seeds: keyed_hash(spec seed, index, kItemStream).
constexpr std::uint64_t kItemStream = 0x64617461'73657431ULL;  // "dataset1"
constexpr double kRadPerDeg = std::numbers::pi / 180.0;

std::string number_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Fixed-point text: the scene file holds exactly the values the run uses.
std::string fx(double v, int decimals = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s(buf);
  if (s[0] == '-' && s.find_first_not_of("0.", 1) == std::string::npos) s.erase(0, 1);  // -0
  return s;
}

// `v` as the scene file holds it (fx) and as its reader reads it back.
double rounded(double v, int decimals) {
  return std::stod(fx(v, decimals));
}

std::string range_text(NumberRange r) {
  if (r.lo == r.hi) return number_text(r.lo);
  std::string t(1, '[');
  t.append(number_text(r.lo)).append(", ").append(number_text(r.hi)).append("]");
  return t;
}

// A number or [lo, hi], each within [min, max] (min exclusive when `min_exclusive`).
NumberRange read_range(const Fields& f, const std::string& key, NumberRange fallback, double min,
                       double max, bool min_exclusive = false) {
  if (!f.given(key)) return fallback;
  const YAML::Node n = f.node()[key];
  NumberRange r;
  if (n.IsSequence()) {
    if (n.size() != 2) f.fail_value(key, "a number or a list [lo, hi] of two numbers");
    r.lo = f.element_number(key, n[0], 0);
    r.hi = f.element_number(key, n[1], 1);
    if (!(r.lo <= r.hi)) f.fail_value(key, "lo <= hi in [lo, hi]");
  } else {
    r.lo = r.hi = f.number(key);
  }
  const bool low_ok = min_exclusive ? r.lo > min : r.lo >= min;
  if (!low_ok || !(r.hi <= max)) {
    std::string c = key + (min_exclusive ? " > " : " >= ") + number_text(min);
    if (std::isfinite(max)) c += " and <= " + number_text(max);
    f.fail_value(key, c);
  }
  return r;
}

// What a scene file accepts for one key (docs/scene-format.md), from the declarations its reader
// uses: the option table (formats/config/option_table.cpp) and the bathymetry generators' parameters
// (formats/config/bathy_spec_parser.cpp) and the object table (include/sonarsynth/object_types.hpp). The
// keys of a `materials` entry are bounded in the scene reader's code (formats/config/scene_file.cpp);
// their bounds are restated here.
struct SceneBound {
  std::string key;
  double lo = -kInf, hi = kInf;
  bool lo_open = false, hi_open = false;
  bool accepts(double v) const {
    return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  std::string constraint() const {
    std::string c = key;
    if (std::isfinite(lo)) c += (lo_open ? " > " : " >= ") + number_text(lo);
    if (std::isfinite(hi)) {
      c += std::string(std::isfinite(lo) ? " and" : "") + (hi_open ? " < " : " <= ") +
           number_text(hi);
    }
    return c;
  }
};

SceneBound scene_bound(std::string_view scene_key) {
  const std::string key(scene_key);
  const auto from_param = [&](const bathy_spec::Param& p) {
    return SceneBound{key, p.lo, p.hi, p.lo_open, p.hi_open};
  };
  constexpr std::string_view kComponents = "bathymetry.generate.components.";
  if (scene_key.starts_with(kComponents)) {
    const std::string_view rest = scene_key.substr(kComponents.size());
    const std::size_t dot = rest.find('.');
    if (const auto* c = bathy_spec::find_component(rest.substr(0, dot))) {
      for (const bathy_spec::Param& p : c->params) {
        if (p.key == rest.substr(dot + 1)) return from_param(p);
      }
    }
  } else if (scene_key == "bathymetry.generate.depth_m") {
    return from_param(bathy_spec::depth_param());
  } else if (scene_key == "materials.texture_shape") {
    return {key, 0.0, 1e6};
  } else if (scene_key == "materials.reflectivity") {
    return {key, 0.0, 1.0};
  } else if (scene_key == "objects.scale") {
    const ObjectParam& p = *find_object_type("mesh")->param("scale");
    return {key, p.lo, p.hi, p.lo_open, false};
  } else {
    const options::Option& o = options::at(scene_key);
    return {key, o.lo, o.hi, o.lo_open, false};
  }
  throw std::logic_error("dataset spec: no scene key " + key);
}

// Every value of `r` as the item's scene file will hold it (rounded to `decimals`) must be one
// that the scene file accepts for `scene_key`.
void check_scene_bound(const Fields& f, const std::string& key, NumberRange r, int decimals,
                       std::string_view scene_key) {
  const SceneBound b = scene_bound(scene_key);
  if (!b.accepts(rounded(r.lo, decimals)) || !b.accepts(rounded(r.hi, decimals))) {
    f.fail_value(key, b.constraint() + " in the item's scene file (docs/scene-format.md), " +
                          "every value as written there (to " + std::to_string(decimals) +
                          " decimals)");
  }
}

// A range of a key the scene file bounds: a number or [lo, hi] within `scene_key`'s bounds.
NumberRange read_scene_range(const Fields& f, const std::string& key, NumberRange fallback,
                             std::string_view scene_key, int decimals) {
  const NumberRange r = read_range(f, key, fallback, -kInf, kInf);
  if (f.given(key)) check_scene_bound(f, key, r, decimals, scene_key);
  return r;
}

// A name, a list of names or {name: weight}; every name must pass `valid` (else `valid_text`).
template <class Valid>
WeightedChoice read_choice(const Fields& f, const std::string& key, WeightedChoice fallback,
                           Valid valid, const std::string& valid_text) {
  if (!f.given(key)) return fallback;
  const YAML::Node n = f.node()[key];
  WeightedChoice c;
  if (n.IsScalar()) {
    c.names.push_back(n.Scalar());
    c.weights.push_back(1.0);
  } else if (n.IsSequence()) {
    for (std::size_t i = 0; i < n.size(); ++i) {
      c.names.push_back(f.scalar_text(key + "[" + std::to_string(i) + "]", n[i]));
      c.weights.push_back(1.0);
    }
  } else if (n.IsMap()) {
    const Fields m(n, f.file(), f.key_path(key));
    for (const auto& kv : n) {
      const std::string name = f.scalar_text(key, kv.first);
      c.names.push_back(name);
      c.weights.push_back(m.number_in(name, 1.0, 0.0, kInf, true));
    }
  }
  if (c.names.empty()) f.fail_value(key, "a name, a list of names or a map {name: weight}");
  for (const std::string& name : c.names) {
    if (!valid(name)) {
      f.fail(key, "'" + name + "'. Violated constraint: one of " + valid_text);
    }
  }
  return c;
}

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// Fields of the draws (ItemDraws keys); new fields take new numbers, existing ones keep theirs
// (a spec that does not use a new field draws the scene it drew before).
enum Field : std::uint64_t {
  kDepth = 1,
  kMaterial,
  kSlope,
  kSlopeAzimuth,
  kRoughRms,
  kRoughWavelength,
  kRipplesOn,
  kRippleWavelength,
  kRippleAmplitude,
  kRippleAzimuth,
  kObjectCount,
  kObject,  // sub = 16 * object + attribute (ObjectAttribute)
  kLineHeading,
  kAltitude,
  kSpeed,
  kPreset,
  kRange,
  kNoiseModel,
  kSnr,
  // Domain randomisation knobs (kKnobs).
  kFrequency = 20,
  kAltitudeTimeConstant,
  kRoll,
  kPitch,
  kYaw,
  kHeave,
  kDisturbancePeriod,
  kAltitudeWander,
  kHeadingWander,
  kWanderPeriod,
  kGain,
  kSeabedMedian,
  kTextureShape,
  kReflectivity,
  kRoughPersistence,
  kRippleBandwidth,
  kRippleVariation,
  kRippleAsymmetry,
};
static_assert(kSnr == 19 && kFrequency == 20, "existing fields keep their numbers");

// Attributes of object k (sub-index 16 k + attribute of kObject).
enum ObjectAttribute : std::uint64_t {
  kType = 0,
  kAlong = 1,
  kAcross = 2,
  kSide = 3,
  kHeading = 4,
  kEmbed = 5,
  kDiameter = 6,
  kLength = 7,
  kWidth = 8,
  kHeight = 9,
  kModel = 10,
  kScale = 11,
};

// An optional knob of domain randomisation: a spec key whose last part is the key it sets in the
// scene file, the scene key that bounds it, its draw field and its decimals in the scene file.
struct Knob {
  std::string_view key;
  std::string_view scene_key;
  Field field;
  int decimals;
};

// docs/dataset.md, "Domain randomisation": one line per knob.
constexpr Knob kKnobs[] = {
    {"seabed.texture_shape", "materials.texture_shape", kTextureShape, 3},
    {"seabed.reflectivity", "materials.reflectivity", kReflectivity, 4},
    {"seabed.roughness.persistence", "bathymetry.generate.components.fbm.persistence",
     kRoughPersistence, 3},
    {"seabed.ripples.bandwidth", "bathymetry.generate.components.ripples.bandwidth",
     kRippleBandwidth, 3},
    {"seabed.ripples.amplitude_variation",
     "bathymetry.generate.components.ripples.amplitude_variation", kRippleVariation, 3},
    {"seabed.ripples.asymmetry", "bathymetry.generate.components.ripples.asymmetry",
     kRippleAsymmetry, 3},
    {"survey.altitude_time_constant_s", "survey.altitude_time_constant_s", kAltitudeTimeConstant,
     3},
    {"survey.disturbance.roll_deg", "survey.disturbance.roll_deg", kRoll, 3},
    {"survey.disturbance.pitch_deg", "survey.disturbance.pitch_deg", kPitch, 3},
    {"survey.disturbance.yaw_deg", "survey.disturbance.yaw_deg", kYaw, 3},
    {"survey.disturbance.heave_m", "survey.disturbance.heave_m", kHeave, 3},
    {"survey.disturbance.period_s", "survey.disturbance.period_s", kDisturbancePeriod, 3},
    {"survey.disturbance.altitude_m", "survey.disturbance.altitude_m", kAltitudeWander, 3},
    {"survey.disturbance.heading_wander_deg", "survey.disturbance.heading_wander_deg",
     kHeadingWander, 3},
    {"survey.disturbance.wander_period_s", "survey.disturbance.wander_period_s", kWanderPeriod, 3},
    {"sonar.frequency_khz", "sonar.frequency_khz", kFrequency, 3},
    {"output.gain_db", "output.gain_db", kGain, 2},
    {"output.seabed_median_dbfs", "output.seabed_median_dbfs", kSeabedMedian, 2},
};

std::string_view section_of(std::string_view key) {
  return key.substr(0, key.rfind('.'));
}
std::string name_of(std::string_view key) {
  return std::string(key.substr(key.rfind('.') + 1));
}

// The keys of a spec section: `keys` and the knobs of `section`.
std::set<std::string> with_knobs(std::set<std::string> keys, std::string_view section) {
  for (const Knob& k : kKnobs) {
    if (section_of(k.key) == section) keys.insert(name_of(k.key));
  }
  return keys;
}

// Reads the knobs of `section` (the map `f`) that the spec gives.
void read_knobs(const Fields& f, std::string_view section, DatasetSpec& s) {
  for (const Knob& k : kKnobs) {
    if (section_of(k.key) != section || !f.given(name_of(k.key))) continue;
    s.knobs[std::string(k.key)] = read_scene_range(f, name_of(k.key), {}, k.scene_key, k.decimals);
  }
}

// The highest value of knob `key`, or `fallback` (the scene's default) when it is left out.
double knob_hi(const DatasetSpec& s, const std::string& key, double fallback = 0.0) {
  const auto it = s.knobs.find(key);
  return it == s.knobs.end() ? fallback : it->second.hi;
}

// The file of a mesh model as a spec names it: the name of a shipped model (samples/models,
// docs/dataset.md) or a path relative to the spec file's directory; absolute either way.
std::filesystem::path model_file(const std::string& spec_file, const std::string& name) {
  namespace fs = std::filesystem;
  if (name.find('/') == std::string::npos && name.find('.') == std::string::npos) {
    return fs::path(SONARSYNTH_MODELS_DIR) / (name + ".obj");
  }
  std::error_code ec;
  const fs::path p = fs::absolute(fs::path(spec_file).parent_path() / name, ec);
  return p.lexically_normal();
}

NumberRange read_object_range(const Fields& d, const ObjectType& type, const ObjectSpecKey& k);

// The mesh type of a spec (`objects.types.mesh`): its models read at load, so that a missing or
// unreadable file is an error of the spec, and their size sets the grid's margin.
void read_mesh_type(const Fields& d, DatasetObjectType& t) {
  d.only({"weight", "models", "scale"});
  if (!d.given("models")) {
    d.fail("models",
           "missing (a map {model: weight}: a path relative to the spec file or a shipped "
           "model, mine or wreck)");
  }
  t.models = read_choice(
      d, "models", {}, [](const std::string& n) { return !n.empty(); }, "non-empty names");
  for (const std::string& name : t.models.names) {
    const std::filesystem::path file = model_file(d.file(), name);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) {
      d.fail("models", "'" + name + "'. Violated constraint: an existing model file (" +
                           file.string() +
                           " is none; a path is relative to the spec file's directory, a name "
                           "without '/' or '.' is a shipped model: mine, wreck)");
    }
    try {
      const mesh_file::Model m = mesh_file::load(file.string(), false);
      for (const Eigen::Vector3d& v : m.mesh.vertex_m) {
        t.model_radius_m = std::max(t.model_radius_m, std::hypot(v.x(), v.y()));
      }
    } catch (const InputError& e) {
      d.fail("models", "'" + name + "': " + e.what());
    }
    t.model_files.push_back(file.string());
  }
  const ObjectType& mesh = *find_object_type("mesh");
  t.scale = read_object_range(d, mesh, mesh.spec_keys.front());
  check_scene_bound(d, "scale", t.scale, 3, "objects.scale");
}

// The object types a spec draws, in the order of the type pick's weights (DatasetSpec::
// object_types): a new type goes at the end, so that the specs without it draw as before.
constexpr std::string_view kSpecTypeOrder[] = {"rock", "box", "pipe", "moored", "mesh"};

// The keys of `objects.types`: the types of the object table a spec draws.
std::set<std::string> spec_type_names() {
  std::set<std::string> names;
  for (const ObjectType& type : object_types()) {
    if (type.in_dataset_spec()) names.insert(std::string(type.name));
  }
  if (names.size() != std::size(kSpecTypeOrder) ||
      !std::all_of(std::begin(kSpecTypeOrder), std::end(kSpecTypeOrder),
                   [&](std::string_view n) { return names.count(std::string(n)) == 1; })) {
    throw std::logic_error("dataset spec: kSpecTypeOrder lists other types than the table");
  }
  return names;
}

// The member of DatasetObjectType that holds the range of spec key `key` (ObjectSpecKey).
NumberRange DatasetObjectType::*range_member(std::string_view key) {
  return key == "diameter_m" ? &DatasetObjectType::diameter_m
         : key == "length_m" ? &DatasetObjectType::length_m
         : key == "width_m"  ? &DatasetObjectType::width_m
         : key == "height_m" ? &DatasetObjectType::height_m
                             : &DatasetObjectType::scale;
}

// The draw of spec key `key` of an object (ItemDraws sub-index 16 k + attribute).
ObjectAttribute attribute_of(std::string_view key) {
  return key == "diameter_m" ? kDiameter
         : key == "length_m" ? kLength
         : key == "width_m"  ? kWidth
         : key == "height_m" ? kHeight
                             : kScale;
}

// The range of a spec key of an object type (ObjectSpecKey), within the bounds of the scene
// parameter it draws (include/sonarsynth/object_types.hpp, the scene reader's own checks), with
// their message. Sizes are written to 1 mm: each must stay > 0 there.
NumberRange read_object_range(const Fields& d, const ObjectType& type, const ObjectSpecKey& k) {
  const ObjectParam& p = *type.param(k.param);
  const std::string key(k.key);
  const NumberRange r = read_range(d, key, {k.spec_default, k.spec_default}, -kInf, kInf);
  if (!p.accepts(r.lo) || !p.accepts(r.hi)) d.fail_value(key, p.constraint(k.key));
  if (p.unit == "m" && !(rounded(r.lo, 3) > 0.0)) {
    d.fail_value(key, key + " >= 0.0005 (written to 1 mm)");
  }
  return r;
}

// An entry of `objects.types` (docs/dataset.md): its weight and the ranges of its keys.
DatasetObjectType read_object_type(const Fields& d, const ObjectType& type) {
  DatasetObjectType ot;
  ot.type = std::string(type.name);
  ot.weight = d.number_in("weight", 1.0, 0.0, kInf, true);
  if (type.shape == ObjectShape::kMesh) {
    read_mesh_type(d, ot);
    return ot;
  }
  std::set<std::string> keys{"weight"};
  for (const ObjectSpecKey& k : type.spec_keys) keys.insert(std::string(k.key));
  d.only(keys);
  for (const ObjectSpecKey& k : type.spec_keys) {
    ot.*range_member(k.key) = read_object_range(d, type, k);
  }
  if (type.name == "moored" && !(rounded(ot.height_m.lo, 3) > rounded(ot.diameter_m.hi, 3) / 2.0)) {
    d.fail_value("height_m",
                 "the lowest height_m > half the largest diameter_m (the "
                 "target's centre above the seabed)");
  }
  return ot;
}

// Counter-based draws of one item: each value is keyed by (field, sub-index), so a change to
// one field of the spec leaves the draws of the others as they were.
class ItemDraws {
 public:
  explicit ItemDraws(std::uint64_t seed) : seed_(seed) {}
  double unit(std::uint64_t field, std::uint64_t sub = 0) const {
    return static_cast<double>(keyed_hash(seed_, field, sub) >> 11) * 0x1.0p-53;
  }
  double in(NumberRange r, std::uint64_t field, std::uint64_t sub = 0) const {
    return r.lo == r.hi ? r.lo : r.lo + unit(field, sub) * (r.hi - r.lo);
  }
  int integer(NumberRange r, std::uint64_t field, std::uint64_t sub = 0) const {
    const double span = r.hi - r.lo + 1.0;
    return static_cast<int>(r.lo + std::min(std::floor(unit(field, sub) * span), span - 1.0));
  }
  template <class Weights>
  std::size_t pick(const Weights& w, std::uint64_t field, std::uint64_t sub = 0) const {
    double total = 0.0;
    for (double x : w) total += x;
    double u = unit(field, sub) * total;
    for (std::size_t i = 0; i + 1 < w.size(); ++i) {
      if (u < w[i]) return i;
      u -= w[i];
    }
    return w.size() - 1;
  }

 private:
  std::uint64_t seed_;
};

// A YAML double-quoted scalar.
std::string yaml_quoted(const std::string& text) {
  std::string q = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

// Writes the draws of one item: each value as the scene text holds it (fx), recorded under its
// spec key in the item's drawn values (DatasetItemScene::drawn_numbers, drawn_names).
class ItemWriter {
 public:
  ItemWriter(const DatasetSpec& s, DatasetItemScene& item)
      : spec_(s), item_(item), draws_(item.seed) {}
  const ItemDraws& draws() const { return draws_; }
  // `v` as written with `decimals`, recorded under `key`.
  std::string number(const std::string& key, double v, int decimals = 3) {
    std::string t = fx(v, decimals);
    item_.drawn_numbers[key] = std::stod(t);
    return t;
  }
  std::string draw(const std::string& key, NumberRange r, std::uint64_t field, int decimals = 3,
                   std::uint64_t sub = 0) {
    return number(key, draws_.in(r, field, sub), decimals);
  }
  const std::string& name(const std::string& key, const WeightedChoice& c, std::uint64_t field) {
    const std::string& n = c.names[draws_.pick(c.weights, field)];
    item_.drawn_names[key] = n;
    return n;
  }
  void text(const std::string& key, const std::string& value) { item_.drawn_names[key] = value; }
  // ", key: value" for each knob of `section` the spec gives, in the order of kKnobs.
  std::string knob_pairs(std::string_view section) {
    std::string out;
    for (const auto& [name, value] : knobs(section)) out += ", " + name + ": " + value;
    return out;
  }
  // "<indent>key: value\n" for each knob of `section` the spec gives.
  std::string knob_lines(std::string_view section, const std::string& indent) {
    std::string out;
    for (const auto& [name, value] : knobs(section)) out += indent + name + ": " + value + "\n";
    return out;
  }

 private:
  std::vector<std::pair<std::string, std::string>> knobs(std::string_view section) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const Knob& k : kKnobs) {
      const auto it = spec_.knobs.find(std::string(k.key));
      if (section_of(k.key) != section || it == spec_.knobs.end()) continue;
      out.emplace_back(name_of(k.key), draw(std::string(k.key), it->second, k.field, k.decimals));
    }
    return out;
  }

  const DatasetSpec& spec_;
  DatasetItemScene& item_;
  ItemDraws draws_;
};

// Largest horizontal distance of a point of an object from its position, metres.
double max_object_extent_m(const DatasetSpec& s) {
  double e = 0.0;
  for (const DatasetObjectType& t : s.object_types) {
    switch (find_object_type(t.type)->shape) {
      case ObjectShape::kEllipsoid:  // rock, moored sphere
        e = std::max(e, t.diameter_m.hi);
        break;
      case ObjectShape::kCylinder:  // pipe
        e = std::max(e, t.length_m.hi / 2.0 + t.diameter_m.hi);
        break;
      case ObjectShape::kBox:
        e = std::max(e, std::hypot(t.length_m.hi, t.width_m.hi) / 2.0);
        break;
      case ObjectShape::kMesh:
        e = std::max(e, t.model_radius_m * t.scale.hi);
        break;
    }
  }
  return e;
}

// The side of an item's square grid: it holds the line and its swath whatever the heading, with
// a margin for the largest object.
double grid_side_m(const DatasetSpec& s, double max_range_m) {
  const double half_m = s.line_length_m / 2.0 + std::max(max_range_m, s.across_track_m.hi) +
                        max_object_extent_m(s) + 10.0;
  return 2.0 * std::ceil(half_m / s.cell_m) * s.cell_m;
}

// The constraints of the scene file that tie several keys together (docs/scene-format.md,
// "Checks before the run"), checked on the extremes of the spec's ranges so that no drawn item
// fails them. The seabed's relief under the line and the sensor's motion are bounded as
// docs/dataset.md states ("Validation").
void check_item_constraints(const DatasetSpec& s) {
  const auto fail = [&](const std::string& key, const std::string& value,
                        const std::string& constraint) {
    throw InputError(s.file + ": " + key + " = '" + value +
                     "'. Violated constraint: " + constraint);
  };
  // The presets an item may draw, with the spec's range.
  double min_range_m = kInf, max_range_m = 0.0, max_pings = 0.0;
  const double line_m = s.line_length_m, slowest_m_s = rounded(s.speed_m_s.lo, 3);
  for (const std::string& name : s.sonar_preset.names) {
    SonarConfig c = find_sonar_preset(name)->sonar;
    const double preset_range_m = c.max_range_m;
    c.max_range_m = s.range_m ? rounded(s.range_m->lo, 3) : preset_range_m;
    min_range_m = std::min(min_range_m, c.max_range_m);
    max_range_m = std::max(max_range_m, s.range_m ? s.range_m->hi : preset_range_m);
    max_pings =
        std::max(max_pings, std::floor(line_m / (slowest_m_s * c.effective_ping_period_s())) + 1.0);
  }
  // The generator's size limit on an item's grid.
  const double side_m = grid_side_m(s, max_range_m);
  BathyGenSpec g;
  try {
    g.geometry = BathyGenSpec::centred_geometry(0.0, 0.0, side_m, side_m, s.cell_m);
  } catch (const InputError& e) {
    fail("seabed.cell_m", number_text(s.cell_m),
         std::string(e.what()) + " (an item's grid is " + number_text(side_m) +
             " m across: the line, the swath and the largest object)");
  }
  const RunLimits limits;
  if (!(max_pings <= static_cast<double>(limits.max_pings))) {
    fail("survey.speed_m_s", range_text(s.speed_m_s),
         "an item's line of " + number_text(line_m) +
             " m at the lowest speed and the shortest "
             "range (one ping per two-way travel time) takes " +
             number_text(max_pings) + " pings; at most limits.max_pings = " +
             std::to_string(limits.max_pings) + " of the scene file (docs/scene-format.md)");
  }
  // The seabed under the line, from its depth at the centre: the plane's rise over half the
  // line, 4 rms of the fBm and 3 ripple amplitudes; the sensor's excursions from its altitude:
  // the heave's peak, the altitude wander's (five sinusoids of sqrt(2/5) rms: sqrt(10) rms) and
  // a lagging altitude controller's, at most the relief's span, and at most its lag on the
  // steepest slope (slope x speed x time constant) plus the span of the bumps.
  const double slope = std::tan(s.slope_deg.hi * kRadPerDeg);
  const double bumps_m = 4.0 * s.roughness_rms_m.hi +
                         (s.ripples_probability > 0.0 ? 3.0 * s.ripple_amplitude_m.hi : 0.0);
  const double relief_m = slope * line_m / 2.0 + bumps_m;
  const double tau_s = knob_hi(s, "survey.altitude_time_constant_s");
  const double lag_m =
      tau_s > 0.0 ? std::min(2.0 * relief_m, slope * s.speed_m_s.hi * tau_s + 2.0 * bumps_m) : 0.0;
  const double motion_m = knob_hi(s, "survey.disturbance.heave_m") +
                          std::sqrt(10.0) * knob_hi(s, "survey.disturbance.altitude_m") + lag_m;
  const double lowest_m = rounded(s.altitude_m.lo, 3), highest_m = rounded(s.altitude_m.hi, 3);
  if (!(lowest_m > motion_m)) {
    fail("survey.altitude_m", range_text(s.altitude_m),
         "the lowest altitude > the sensor's motion about it (" + number_text(motion_m) +
             " m: survey.disturbance.heave_m, altitude_m, altitude_time_constant_s): the sensor "
             "must stay above the seabed");
  }
  if (!(rounded(s.depth_m.lo, 3) - relief_m > highest_m + motion_m)) {
    fail("seabed.depth_m", number_text(s.depth_m.lo),
         "the shallowest depth less the seabed's relief under the line (" + number_text(relief_m) +
             " m) > the highest survey.altitude_m (" + number_text(s.altitude_m.hi) +
             " m) plus the sensor's motion (" + number_text(motion_m) +
             " m): the towfish must stay in the water");
  }
  if (!(min_range_m > highest_m + motion_m)) {
    fail(s.range_m ? "sonar.range_m" : "sonar.preset",
         s.range_m ? range_text(*s.range_m) : join(s.sonar_preset.names),
         "the shortest range (" + number_text(min_range_m) + " m) > the highest altitude (" +
             number_text(highest_m) + " m) plus the sensor's motion (" + number_text(motion_m) +
             " m): every ping sees the seabed");
  }
  // The generator's own checks: the depth, the ripples on the grid.
  for (const double depth_m : {s.depth_m.lo, s.depth_m.hi}) {
    g.depth_m = rounded(depth_m, 3);
    try {
      g.validate();
    } catch (const InputError& e) {
      fail("seabed.depth_m", range_text(s.depth_m), e.what());
    }
  }
  if (s.ripples_probability > 0.0) {
    bathy::Ripples r;
    r.wavelength_m = rounded(s.ripple_wavelength_m.lo, 3);
    g.components = {r};
    try {
      g.validate_components();
    } catch (const InputError& e) {
      fail("seabed.ripples.wavelength_m", range_text(s.ripple_wavelength_m), e.what());
    }
  }
}

DatasetSpec parse_spec(const YAML::Node& root, const std::string& file, std::string text) {
  DatasetSpec s;
  s.file = file;
  s.text = std::move(text);
  const Fields top(root, file, "");
  if (!root.IsMap()) throw InputError(file + ": a dataset spec is a map of keys (docs/dataset.md)");
  top.only({"name", "seed", "count", "location", "seabed", "objects", "survey", "sonar", "noise",
            "output", "run"});
  s.name = top.text("name", s.name);
  for (const char c : s.name) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) {
      top.fail_value("name", "letters, digits, '-', '_' and '.' only");
    }
  }
  if (!top.given("seed"))
    top.fail("seed", "missing (an integer is required: items derive from it)");
  s.seed = top.seed("seed", 0);
  if (!top.given("count")) top.fail("count", "missing (the number of items)");
  const std::int64_t count = top.integer("count", 1);
  if (count < 1 || count > 10'000'000) top.fail_value("count", "count >= 1 and <= 10000000");
  s.count = static_cast<std::size_t>(count);

  if (top.has("location")) {
    const Fields l = top.child("location");
    l.only({"lat_deg", "lon_deg"});
    s.lat_deg = l.number_in("lat_deg", s.lat_deg, -80.0, 84.0);
    s.lon_deg = l.number_in("lon_deg", s.lon_deg, -180.0, 180.0);
  }
  if (top.has("seabed")) {
    const Fields b = top.child("seabed");
    b.only(with_knobs({"depth_m", "cell_m", "material", "slope_deg", "roughness", "ripples"},
                      "seabed"));
    s.depth_m = read_range(b, "depth_m", s.depth_m, 0.0, 12000.0, true);
    check_scene_bound(b, "depth_m", s.depth_m, 3, "bathymetry.generate.depth_m");
    s.cell_m = b.number_in("cell_m", s.cell_m, 0.01, 10.0);
    const MaterialTable materials = MaterialTable::defaults();
    std::vector<std::string> material_names;
    for (const Material& m : materials.all()) material_names.push_back(m.name);
    s.material = read_choice(
        b, "material", s.material, [&](const std::string& n) { return materials.contains(n); },
        join(material_names));
    s.slope_deg = read_range(b, "slope_deg", s.slope_deg, 0.0, 30.0);
    read_knobs(b, "seabed", s);
    if (b.has("roughness")) {
      const Fields r = b.child("roughness");
      r.only(with_knobs({"rms_m", "wavelength_m"}, "seabed.roughness"));
      s.roughness_rms_m = read_range(r, "rms_m", s.roughness_rms_m, 0.0, 100.0);
      s.roughness_wavelength_m =
          read_range(r, "wavelength_m", s.roughness_wavelength_m, 0.0, 1e5, true);
      check_scene_bound(r, "wavelength_m", s.roughness_wavelength_m, 3,
                        "bathymetry.generate.components.fbm.wavelength_m");
      read_knobs(r, "seabed.roughness", s);
    }
    if (b.has("ripples")) {
      const Fields r = b.child("ripples");
      r.only(with_knobs({"probability", "wavelength_m", "amplitude_m"}, "seabed.ripples"));
      s.ripples_probability = r.number_in("probability", 1.0, 0.0, 1.0);
      s.ripple_wavelength_m = read_range(r, "wavelength_m", s.ripple_wavelength_m, 0.0, 1e4, true);
      check_scene_bound(r, "wavelength_m", s.ripple_wavelength_m, 3,
                        "bathymetry.generate.components.ripples.wavelength_m");
      s.ripple_amplitude_m = read_range(r, "amplitude_m", s.ripple_amplitude_m, 0.0, 100.0);
      read_knobs(r, "seabed.ripples", s);
    }
  }
  if (top.has("survey")) {
    const Fields v = top.child("survey");
    v.only(with_knobs({"line_length_m", "heading_deg", "altitude_m", "speed_m_s", "disturbance"},
                      "survey"));
    s.line_length_m = v.number_in("line_length_m", s.line_length_m, 1.0, 1e5);
    s.line_heading_deg = read_range(v, "heading_deg", s.line_heading_deg, -360.0, 720.0);
    s.altitude_m = read_range(v, "altitude_m", s.altitude_m, 0.0, 12000.0, true);
    check_scene_bound(v, "altitude_m", s.altitude_m, 3, "survey.altitude_m");
    s.speed_m_s = read_range(v, "speed_m_s", s.speed_m_s, 0.0, 50.0, true);
    check_scene_bound(v, "speed_m_s", s.speed_m_s, 3, "survey.speed_m_s");
    read_knobs(v, "survey", s);
    if (v.has("disturbance")) {
      const Fields d = v.child("disturbance");
      d.only(with_knobs({}, "survey.disturbance"));
      read_knobs(d, "survey.disturbance", s);
    }
  }
  if (top.has("sonar")) {
    const Fields v = top.child("sonar");
    v.only(with_knobs({"preset", "range_m", "samples"}, "sonar"));
    s.sonar_preset = read_choice(
        v, "preset", s.sonar_preset,
        [](const std::string& n) { return find_sonar_preset(n) != nullptr; }, sonar_preset_names());
    if (v.given("range_m")) {
      s.range_m = read_range(v, "range_m", {}, 0.0, 10000.0, true);
      check_scene_bound(v, "range_m", *s.range_m, 3, "sonar.range_m");
    }
    if (v.given("samples")) {
      const std::int64_t n = v.integer("samples", 1024);
      // At most what XTF readers accept (docs/scene-format.md `sonar.samples`; a spec has no
      // output.allow_more_than_8192_samples).
      if (n < 16 || n > 8192) v.fail_value("samples", "samples >= 16 and <= 8192");
      s.samples = static_cast<std::size_t>(n);
    }
    read_knobs(v, "sonar", s);
  }
  if (top.has("noise")) {
    const Fields v = top.child("noise");
    v.only({"model", "snr_db"});
    s.noise_model = read_choice(
        v, "model", s.noise_model,
        [](const std::string& n) { return n == "none" || n == "paper" || n == "speckle"; },
        "none, paper, speckle");
    s.snr_db = read_range(v, "snr_db", s.snr_db, -100.0, 200.0);
    check_scene_bound(v, "snr_db", s.snr_db, 2, "noise.snr_db");
  }
  if (top.has("output")) {
    const Fields v = top.child("output");
    v.only(with_knobs({}, "output"));
    if (v.given("gain_db") && v.given("seabed_median_dbfs")) {
      v.fail("gain_db",
             "give gain_db (a fixed gain) or seabed_median_dbfs (the automatic gain's target), "
             "not both: a fixed gain ignores the target (docs/scene-format.md)");
    }
    read_knobs(v, "output", s);
  }
  double max_range_m = 0.0;
  for (const std::string& p : s.sonar_preset.names) {
    max_range_m = std::max(max_range_m, find_sonar_preset(p)->sonar.max_range_m);
  }
  if (s.range_m) max_range_m = s.range_m->hi;

  if (top.has("objects")) {
    const Fields o = top.child("objects");
    o.only({"count", "burial", "heading_deg", "across_track_m", "types"});
    s.object_count = read_range(o, "count", s.object_count, 0.0, 10000.0);
    if (s.object_count.lo != std::floor(s.object_count.lo) ||
        s.object_count.hi != std::floor(s.object_count.hi)) {
      o.fail_value("count", "integers");
    }
    s.burial = read_range(o, "burial", s.burial, 0.0, 0.99);
    s.object_heading_deg = read_range(o, "heading_deg", s.object_heading_deg, -360.0, 720.0);
    s.across_track_m = read_range(o, "across_track_m", s.across_track_m, 0.0, max_range_m);
    if (o.has("types")) {
      const Fields t = o.child("types");
      t.only(spec_type_names());
      for (const std::string_view name : kSpecTypeOrder) {
        if (t.has(std::string(name))) {
          s.object_types.push_back(
              read_object_type(t.child(std::string(name)), *find_object_type(name)));
        }
      }
    }
    if (s.object_count.hi > 0 && s.object_types.empty()) {
      o.fail("types", "missing (objects.count allows objects: give at least one type)");
    }
  }
  check_item_constraints(s);
  if (top.has("run")) {
    const Fields r = top.child("run");
    r.only({"quality", "products", "split", "display_window_db"});
    if (r.given("display_window_db")) {
      const std::vector<double> w = r.numbers("display_window_db", 2);
      if (!(w[0] < w[1]) || w[1] - w[0] > 200.0 || w[0] < -300.0 || w[1] > 100.0) {
        r.fail_value("display_window_db",
                     "[lo, hi] with -300 <= lo < hi <= 100 and hi - lo <= 200 (dB)");
      }
      s.display_window_db = {w[0], w[1]};
    }
    s.quality = r.text("quality", s.quality);
    if (s.quality != "fast" && s.quality != "default" && s.quality != "high") {
      r.fail_value("quality", "one of fast, default, high");
    }
    if (r.has("products")) {
      const Fields p = r.child("products");
      p.only({"mosaic", "waterfalls", "truth", "labels"});
      s.mosaic = p.boolean("mosaic", s.mosaic);
      s.waterfalls = p.boolean("waterfalls", s.waterfalls);
      s.truth = p.boolean("truth", s.truth);
      if (p.has("labels")) {
        s.labels = yaml::read_label_output(p.child("labels"), s.truth);
        YAML::Emitter e;
        e.SetMapFormat(YAML::Flow);
        e.SetSeqFormat(YAML::Flow);
        e << p.node()["labels"];
        s.labels_yaml = e.c_str();
      }
    }
    if (r.has("split")) {
      const Fields p = r.child("split");
      p.only({"train", "val", "test"});
      s.split = true;
      s.split_train = p.number_in("train", 0.0, 0.0, 1.0);
      s.split_val = p.number_in("val", 0.0, 0.0, 1.0);
      s.split_test = p.number_in("test", 0.0, 0.0, 1.0);
      if (std::abs(s.split_train + s.split_val + s.split_test - 1.0) > 1e-9) {
        r.fail("split",
               "train + val + test = " + number_text(s.split_train + s.split_val + s.split_test) +
                   ". Violated constraint: the fractions sum to 1");
      }
    }
  }
  YAML::Node without_count = YAML::Clone(root);
  without_count.remove("count");
  YAML::Emitter e;
  e << without_count;
  s.identity = e.c_str();
  return s;
}

// Object k of an item as an entry of the scene's `objects`: its type, its place beside the
// line (forward (fe, fn), starboard (se, sn)), pose and size.
std::string object_entry(const DatasetSpec& s, ItemWriter& w, DatasetItemScene& item, int k,
                         const std::vector<double>& type_weights, double fe, double fn, double se,
                         double sn) {
  const ItemDraws& d = w.draws();
  std::ostringstream y;
  const std::string o = "objects[" + std::to_string(k) + "].";
  const auto key = [&](ObjectAttribute attribute) {
    return 16 * static_cast<std::uint64_t>(k) + attribute;
  };
  const auto draw = [&](const std::string& name, NumberRange r, ObjectAttribute a) {
    return w.draw(o + name, r, kObject, 3, key(a));
  };
  const DatasetObjectType& t = s.object_types[d.pick(type_weights, kObject, key(kType))];
  w.text(o + "type", t.type);
  const double along = (d.unit(kObject, key(kAlong)) - 0.5) * 0.8 * s.line_length_m;
  const double across = d.in(s.across_track_m, kObject, key(kAcross)) *
                        (d.unit(kObject, key(kSide)) < 0.5 ? -1.0 : 1.0);
  w.number(o + "along_track_m", along);
  w.number(o + "across_track_m", across);
  const double east = along * fe + across * se, north = along * fn + across * sn;
  ++item.object_counts[t.type];
  y << "  - {type: " << t.type << ", id: " << k + 1 << ", name: " << t.type << "-" << k + 1
    << ", position: {east_m: " << fx(east) << ", north_m: " << fx(north)
    << "}, heading_deg: " << draw("heading_deg", s.object_heading_deg, kHeading);
  const ObjectType& type = *find_object_type(t.type);
  if (type.shape == ObjectShape::kMesh) {
    const std::size_t m = d.pick(t.models.weights, kObject, key(kModel));
    w.text(o + "model", t.models.names[m]);
    y << ", file: " << yaml_quoted(t.model_files[m]);
  }
  // The drawn keys, as the scene entry names them: size_m's elements as one list.
  for (std::size_t i = 0; i < type.spec_keys.size(); ++i) {
    const ObjectSpecKey& sk = type.spec_keys[i];
    const std::string value =
        draw(std::string(sk.key), t.*range_member(sk.key), attribute_of(sk.key));
    const bool list = sk.param != sk.key;
    const bool first = !list || sk.index == 0, last = !list || i + 1 == type.spec_keys.size() ||
                                                      type.spec_keys[i + 1].param != sk.param;
    y << (first ? ", " + std::string(sk.param) + ": " + (list ? "[" : "") : ", ") << value
      << (list && last ? "]" : "");
  }
  if (type.takes("embed")) y << ", embed: " << draw("burial", s.burial, kEmbed);
  y << "}\n";
  return y.str();
}

}  // namespace

DatasetSpec load_dataset_spec(const std::string& path) {
  std::error_code ec;
  if (path.empty())
    throw InputError("dataset spec: '' (an empty path). Violated constraint: a file");
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path + ": " +
                     (std::filesystem::exists(path, ec) ? "not a regular file" : "no such file") +
                     " (the dataset spec must be a YAML file)");
  }
  const auto bytes = std::filesystem::file_size(path, ec);
  if (ec || bytes > kMaxDatasetSpecBytes) {
    throw InputError(path + ": " +
                     (ec ? std::string("cannot read its size") : std::to_string(bytes) + " bytes") +
                     ". Violated constraint: a dataset spec of at most " +
                     std::to_string(kMaxDatasetSpecBytes) + " bytes");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read the dataset spec");
  std::string text(static_cast<std::size_t>(bytes), '\0');
  in.read(text.data(), static_cast<std::streamsize>(bytes));
  text.resize(static_cast<std::size_t>(in.gcount()));
  return load_dataset_spec_from_string(text, path);
}

DatasetSpec load_dataset_spec_from_string(const std::string& yaml_text, const std::string& name) {
  if (yaml_text.size() > kMaxDatasetSpecBytes) {
    throw InputError(name + ": " + std::to_string(yaml_text.size()) +
                     " bytes. Violated constraint: a dataset spec of at most " +
                     std::to_string(kMaxDatasetSpecBytes) + " bytes");
  }
  const YAML::Node root = yaml::load_string(yaml_text, name);
  return yaml::with_file_errors(name, [&] { return parse_spec(root, name, yaml_text); });
}

std::string dataset_item_split(const DatasetSpec& spec, std::size_t index) {
  if (!spec.split) return "";
  // Test first, then val among the rest: count_test(n) = round(n f_test) and count_val(n) =
  // round(m g) over the m items not in test with g = f_val / (1 - f_test). Both round-offs are
  // within 1/2, so every split holds n f +- 1 of any first n items.
  const auto rounded = [](double n, double f) { return std::floor(n * f + 0.5); };
  const auto i = static_cast<double>(index);
  const double ft = spec.split_test;
  if (rounded(i + 1.0, ft) > rounded(i, ft)) return "test";
  const double g = ft < 1.0 ? std::min(1.0, spec.split_val / (1.0 - ft)) : 0.0;
  const double j = i - rounded(i, ft);  // items before this one not in test
  if (rounded(j + 1.0, g) > rounded(j, g)) return "val";
  return "train";
}

std::uint64_t dataset_item_seed(const DatasetSpec& spec, std::size_t index) {
  return keyed_hash(spec.seed, static_cast<std::uint64_t>(index), kItemStream);
}

DatasetItemScene dataset_item_scene(const DatasetSpec& s, std::size_t index) {
  if (index >= s.count) {
    throw InputError(s.file + ": item " + std::to_string(index) +
                     " is beyond count = " + std::to_string(s.count));
  }
  DatasetItemScene item;
  item.index = index;
  item.seed = dataset_item_seed(s, index);
  ItemWriter w(s, item);
  const ItemDraws& d = w.draws();

  const std::string& preset = w.name("sonar.preset", s.sonar_preset, kPreset);
  const double range_m =
      s.range_m ? d.in(*s.range_m, kRange) : find_sonar_preset(preset)->sonar.max_range_m;
  const double side_m = grid_side_m(s, s.range_m ? s.range_m->hi : range_m);

  std::ostringstream y;
  char idx[32];
  std::snprintf(idx, sizeof idx, "%06zu", index);
  y << "# Item " << index << " of dataset '" << s.name << "' (seed " << item.seed
    << ") (docs/dataset.md)\n";
  y << "name: " << s.name << "-" << idx << "\n";
  y << "seed: " << item.seed << "\n";
  y << "bathymetry:\n  generate:\n";
  y << "    centre: {lat_deg: " << fx(s.lat_deg, 6) << ", lon_deg: " << fx(s.lon_deg, 6) << "}\n";
  y << "    size_m: [" << fx(side_m) << ", " << fx(side_m) << "]\n";
  y << "    cell_m: " << fx(s.cell_m, 4) << "\n";
  y << "    depth_m: " << w.draw("seabed.depth_m", s.depth_m, kDepth) << "\n";
  y << "    components:\n";
  y << "      - {type: plane, slope_deg: " << w.draw("seabed.slope_deg", s.slope_deg, kSlope)
    << ", downslope_azimuth_deg: "
    << w.number("seabed.downslope_azimuth_deg", 360.0 * d.unit(kSlopeAzimuth)) << "}\n";
  const double rms = d.in(s.roughness_rms_m, kRoughRms);
  if (rms > 0.0) {
    y << "      - {type: fbm, rms_m: " << w.number("seabed.roughness.rms_m", rms, 4)
      << ", wavelength_m: "
      << w.draw("seabed.roughness.wavelength_m", s.roughness_wavelength_m, kRoughWavelength)
      << ", octaves: 6" << w.knob_pairs("seabed.roughness") << "}\n";
  }
  const bool ripples = d.unit(kRipplesOn) < s.ripples_probability;
  w.number("seabed.ripples", ripples ? 1.0 : 0.0, 0);
  if (ripples) {
    y << "      - {type: ripples, wavelength_m: "
      << w.draw("seabed.ripples.wavelength_m", s.ripple_wavelength_m, kRippleWavelength)
      << ", amplitude_m: "
      << w.draw("seabed.ripples.amplitude_m", s.ripple_amplitude_m, kRippleAmplitude, 4)
      << ", crest_azimuth_deg: "
      << w.number("seabed.ripples.crest_azimuth_deg", 180.0 * d.unit(kRippleAzimuth))
      << w.knob_pairs("seabed.ripples") << "}\n";
  }
  const std::string& material = w.name("seabed.material", s.material, kMaterial);
  if (const std::string m = w.knob_pairs("seabed"); !m.empty()) {
    y << "materials:\n  - {name: " << material << m << "}\n";
  }
  y << "seabed:\n  material: " << material << "\n";

  // The line through the grid centre; objects along it within its middle 80 %, either side.
  const double heading_deg = d.in(s.line_heading_deg, kLineHeading);
  w.number("survey.heading_deg", heading_deg);
  const double heading_rad = heading_deg * kRadPerDeg;
  const double fe = std::sin(heading_rad), fn = std::cos(heading_rad);  // forward
  const double se = fn, sn = -fe;                                       // starboard
  const int n_objects = s.object_types.empty() ? 0 : d.integer(s.object_count, kObjectCount);
  w.number("objects.count", n_objects, 0);
  std::vector<double> type_weights;
  for (const auto& t : s.object_types) type_weights.push_back(t.weight);
  if (n_objects > 0) y << "objects:\n";
  for (int k = 0; k < n_objects; ++k) {
    y << object_entry(s, w, item, k, type_weights, fe, fn, se, sn);
  }
  const double h = s.line_length_m / 2.0;
  y << "survey:\n  start_time: \"2026-01-01T00:00:00Z\"\n";
  y << "  speed_m_s: " << w.draw("survey.speed_m_s", s.speed_m_s, kSpeed) << "\n";
  y << "  altitude_m: " << w.draw("survey.altitude_m", s.altitude_m, kAltitude) << "\n";
  y << w.knob_lines("survey", "  ");
  if (const std::string m = w.knob_pairs("survey.disturbance"); !m.empty()) {
    y << "  disturbance: {" << m.substr(2) << "}\n";
  }
  y << "  lines:\n    - {name: L1, waypoints: [{east_m: " << fx(-h * fe)
    << ", north_m: " << fx(-h * fn) << "}, {east_m: " << fx(h * fe) << ", north_m: " << fx(h * fn)
    << "}]}\n";
  y << "sonar:\n  preset: " << preset << "\n";
  if (s.range_m) y << "  range_m: " << w.number("sonar.range_m", range_m) << "\n";
  if (s.samples) y << "  samples: " << *s.samples << "\n";
  y << w.knob_lines("sonar", "  ");
  y << "noise:\n  model: " << w.name("noise.model", s.noise_model, kNoiseModel)
    << "\n  snr_db: " << w.draw("noise.snr_db", s.snr_db, kSnr, 2) << "\n";
  // One display window for every image of the dataset (docs/dataset.md, "One display scale").
  y << "output:\n"
    << w.knob_lines("output", "  ") << "  display_window_db: [" << fx(s.display_window_db[0], 2)
    << ", " << fx(s.display_window_db[1], 2) << "]\n"
    << (s.labels_yaml.empty() ? "" : "  labels: " + s.labels_yaml + "\n");
  item.yaml = y.str();
  return item;
}

}  // namespace sonarsynth
