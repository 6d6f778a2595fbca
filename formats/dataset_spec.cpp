// SPDX-License-Identifier: MIT
// Dataset specs (docs/dataset.md): reading and validating the spec file, and drawing item k's
// scene file from it with counter-based random numbers keyed by the item's seed.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/dataset.hpp"
#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/material.hpp"
#include "sonarsynth/sonar_presets.hpp"
#include "yaml_fields.hpp"

namespace sonarsynth {
namespace {

using yaml::Fields;

constexpr double kInf = std::numeric_limits<double>::infinity();
// Salt of the item seeds: keyed_hash(spec seed, index, kItemStream).
constexpr std::uint64_t kItemStream = 0x64617461'73657431ULL;  // "dataset1"

std::string number_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
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

DatasetSpec parse_spec(const YAML::Node& root, const std::string& file, std::string text) {
  DatasetSpec s;
  s.file = file;
  s.text = std::move(text);
  const Fields top(root, file, "");
  if (!root.IsMap()) throw InputError(file + ": a dataset spec is a map of keys (docs/dataset.md)");
  top.only({"name", "seed", "count", "location", "seabed", "objects", "survey", "sonar", "noise",
            "run"});
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
    b.only({"depth_m", "cell_m", "material", "slope_deg", "roughness", "ripples"});
    s.depth_m = read_range(b, "depth_m", s.depth_m, 0.0, 12000.0, true);
    s.cell_m = b.number_in("cell_m", s.cell_m, 0.01, 10.0);
    const MaterialTable materials = MaterialTable::defaults();
    std::vector<std::string> material_names;
    for (const Material& m : materials.all()) material_names.push_back(m.name);
    s.material = read_choice(
        b, "material", s.material, [&](const std::string& n) { return materials.contains(n); },
        join(material_names));
    s.slope_deg = read_range(b, "slope_deg", s.slope_deg, 0.0, 30.0);
    if (b.has("roughness")) {
      const Fields r = b.child("roughness");
      r.only({"rms_m", "wavelength_m"});
      s.roughness_rms_m = read_range(r, "rms_m", s.roughness_rms_m, 0.0, 100.0);
      s.roughness_wavelength_m =
          read_range(r, "wavelength_m", s.roughness_wavelength_m, 0.0, 1e5, true);
    }
    if (b.has("ripples")) {
      const Fields r = b.child("ripples");
      r.only({"probability", "wavelength_m", "amplitude_m"});
      s.ripples_probability = r.number_in("probability", 1.0, 0.0, 1.0);
      s.ripple_wavelength_m = read_range(r, "wavelength_m", s.ripple_wavelength_m, 0.0, 1e4, true);
      s.ripple_amplitude_m = read_range(r, "amplitude_m", s.ripple_amplitude_m, 0.0, 100.0);
    }
  }
  if (top.has("survey")) {
    const Fields v = top.child("survey");
    v.only({"line_length_m", "heading_deg", "altitude_m", "speed_m_s"});
    s.line_length_m = v.number_in("line_length_m", s.line_length_m, 1.0, 1e5);
    s.line_heading_deg = read_range(v, "heading_deg", s.line_heading_deg, -360.0, 720.0);
    s.altitude_m = read_range(v, "altitude_m", s.altitude_m, 0.0, 12000.0, true);
    s.speed_m_s = read_range(v, "speed_m_s", s.speed_m_s, 0.0, 50.0, true);
  }
  if (!(s.depth_m.lo > s.altitude_m.hi)) {
    throw InputError(file + ": seabed.depth_m = '" + number_text(s.depth_m.lo) +
                     "'. Violated constraint: the shallowest depth > the highest "
                     "survey.altitude_m (" +
                     number_text(s.altitude_m.hi) + " m): the towfish must stay in the water");
  }
  if (top.has("sonar")) {
    const Fields v = top.child("sonar");
    v.only({"preset", "range_m", "samples"});
    s.sonar_preset = read_choice(
        v, "preset", s.sonar_preset,
        [](const std::string& n) { return find_sonar_preset(n) != nullptr; }, sonar_preset_names());
    if (v.given("range_m")) s.range_m = read_range(v, "range_m", {}, 0.0, 10000.0, true);
    if (v.given("samples")) {
      const std::int64_t n = v.integer("samples", 1024);
      if (n < 16 || n > 65535) v.fail_value("samples", "samples >= 16 and <= 65535");
      s.samples = static_cast<std::size_t>(n);
    }
  }
  if (top.has("noise")) {
    const Fields v = top.child("noise");
    v.only({"model", "snr_db"});
    s.noise_model = read_choice(
        v, "model", s.noise_model,
        [](const std::string& n) { return n == "none" || n == "paper" || n == "speckle"; },
        "none, paper, speckle");
    s.snr_db = read_range(v, "snr_db", s.snr_db, -100.0, 200.0);
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
      t.only({"rock", "box", "pipe", "moored"});
      for (const std::string type : {"rock", "box", "pipe", "moored"}) {
        if (!t.has(type)) continue;
        const Fields d = t.child(type);
        DatasetObjectType ot;
        ot.type = type;
        ot.weight = d.number_in("weight", 1.0, 0.0, kInf, true);
        if (type == "rock") {
          d.only({"weight", "diameter_m"});
          ot.diameter_m = read_range(d, "diameter_m", {1.0, 1.0}, 0.0, 100.0, true);
        } else if (type == "box") {
          d.only({"weight", "length_m", "width_m", "height_m"});
          ot.length_m = read_range(d, "length_m", {2.0, 2.0}, 0.0, 500.0, true);
          ot.width_m = read_range(d, "width_m", {1.0, 1.0}, 0.0, 500.0, true);
          ot.height_m = read_range(d, "height_m", {1.0, 1.0}, 0.0, 100.0, true);
        } else if (type == "pipe") {
          d.only({"weight", "diameter_m", "length_m"});
          ot.diameter_m = read_range(d, "diameter_m", {0.3, 0.3}, 0.0, 20.0, true);
          ot.length_m = read_range(d, "length_m", {20.0, 20.0}, 0.0, 1e4, true);
        } else {
          d.only({"weight", "diameter_m", "height_m"});
          ot.diameter_m = read_range(d, "diameter_m", {1.0, 1.0}, 0.0, 50.0, true);
          ot.height_m = read_range(d, "height_m", {3.0, 3.0}, 0.0, 1000.0, true);
          if (!(ot.height_m.lo > ot.diameter_m.hi / 2.0)) {
            d.fail_value("height_m",
                         "the lowest height_m > half the largest diameter_m (the "
                         "target's centre above the seabed)");
          }
        }
        s.object_types.push_back(ot);
      }
    }
    if (s.object_count.hi > 0 && s.object_types.empty()) {
      o.fail("types", "missing (objects.count allows objects: give at least one type)");
    }
  }
  if (top.has("run")) {
    const Fields r = top.child("run");
    r.only({"quality", "products", "split"});
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

// Fields of the draws (ItemDraws keys); new fields take new numbers.
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
  kObject,  // sub = 16 * object + attribute
  kLineHeading,
  kAltitude,
  kSpeed,
  kPreset,
  kRange,
  kNoiseModel,
  kSnr,
};

// Fixed-point text: the scene file holds exactly the values the run uses.
std::string fx(double v, int decimals = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s(buf);
  if (s == "-0.000" || s == "-0.00" || s == "-0") s.erase(0, 1);
  return s;
}

double max_object_extent_m(const DatasetSpec& s) {
  double e = 0.0;
  for (const DatasetObjectType& t : s.object_types) {
    if (t.type == "rock" || t.type == "moored") e = std::max(e, t.diameter_m.hi);
    if (t.type == "pipe") e = std::max(e, t.length_m.hi / 2.0 + t.diameter_m.hi);
    if (t.type == "box") e = std::max(e, std::hypot(t.length_m.hi, t.width_m.hi) / 2.0);
  }
  return e;
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
  const ItemDraws d(item.seed);
  constexpr double kRadPerDeg = std::numbers::pi / 180.0;

  const std::string preset = s.sonar_preset.names[d.pick(s.sonar_preset.weights, kPreset)];
  const double range_m =
      s.range_m ? d.in(*s.range_m, kRange) : find_sonar_preset(preset)->sonar.max_range_m;
  // A square grid that holds the line and its swath whatever the heading, with a margin for the
  // largest object.
  const double max_range_m = s.range_m ? s.range_m->hi : range_m;
  const double half_m = s.line_length_m / 2.0 + std::max(max_range_m, s.across_track_m.hi) +
                        max_object_extent_m(s) + 10.0;
  const double side_m = 2.0 * std::ceil(half_m / s.cell_m) * s.cell_m;

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
  y << "    depth_m: " << fx(d.in(s.depth_m, kDepth)) << "\n";
  y << "    components:\n";
  y << "      - {type: plane, slope_deg: " << fx(d.in(s.slope_deg, kSlope))
    << ", downslope_azimuth_deg: " << fx(360.0 * d.unit(kSlopeAzimuth)) << "}\n";
  const double rms = d.in(s.roughness_rms_m, kRoughRms);
  if (rms > 0.0) {
    y << "      - {type: fbm, rms_m: " << fx(rms, 4)
      << ", wavelength_m: " << fx(d.in(s.roughness_wavelength_m, kRoughWavelength))
      << ", octaves: 6}\n";
  }
  if (d.unit(kRipplesOn) < s.ripples_probability) {
    y << "      - {type: ripples, wavelength_m: "
      << fx(d.in(s.ripple_wavelength_m, kRippleWavelength))
      << ", amplitude_m: " << fx(d.in(s.ripple_amplitude_m, kRippleAmplitude), 4)
      << ", crest_azimuth_deg: " << fx(180.0 * d.unit(kRippleAzimuth)) << "}\n";
  }
  y << "seabed:\n  material: " << s.material.names[d.pick(s.material.weights, kMaterial)] << "\n";

  // The line through the grid centre; objects along it within its middle 80 %, either side.
  const double heading_rad = d.in(s.line_heading_deg, kLineHeading) * kRadPerDeg;
  const double fe = std::sin(heading_rad), fn = std::cos(heading_rad);  // forward
  const double se = fn, sn = -fe;                                       // starboard
  const int n_objects = s.object_types.empty() ? 0 : d.integer(s.object_count, kObjectCount);
  std::vector<double> type_weights;
  for (const auto& t : s.object_types) type_weights.push_back(t.weight);
  if (n_objects > 0) y << "objects:\n";
  for (int k = 0; k < n_objects; ++k) {
    const auto key = [&](std::uint64_t attribute) {
      return 16 * static_cast<std::uint64_t>(k) + attribute;
    };
    const DatasetObjectType& t = s.object_types[d.pick(type_weights, kObject, key(0))];
    const double along = (d.unit(kObject, key(1)) - 0.5) * 0.8 * s.line_length_m;
    const double across =
        d.in(s.across_track_m, kObject, key(2)) * (d.unit(kObject, key(3)) < 0.5 ? -1.0 : 1.0);
    const double east = along * fe + across * se, north = along * fn + across * sn;
    const double heading_deg = d.in(s.object_heading_deg, kObject, key(4));
    const double embed = d.in(s.burial, kObject, key(5));
    ++item.object_counts[t.type];
    y << "  - {type: " << t.type << ", id: " << k + 1 << ", name: " << t.type << "-" << k + 1
      << ", position: {east_m: " << fx(east) << ", north_m: " << fx(north)
      << "}, heading_deg: " << fx(heading_deg);
    if (t.type == "rock") {
      y << ", diameter_m: " << fx(d.in(t.diameter_m, kObject, key(6))) << ", embed: " << fx(embed);
    } else if (t.type == "box") {
      y << ", size_m: [" << fx(d.in(t.length_m, kObject, key(7))) << ", "
        << fx(d.in(t.width_m, kObject, key(8))) << ", " << fx(d.in(t.height_m, kObject, key(9)))
        << "], embed: " << fx(embed);
    } else if (t.type == "pipe") {
      y << ", length_m: " << fx(d.in(t.length_m, kObject, key(7)))
        << ", diameter_m: " << fx(d.in(t.diameter_m, kObject, key(6))) << ", embed: " << fx(embed);
    } else {
      y << ", diameter_m: " << fx(d.in(t.diameter_m, kObject, key(6)))
        << ", height_m: " << fx(d.in(t.height_m, kObject, key(9)));
    }
    y << "}\n";
  }
  const double h = s.line_length_m / 2.0;
  y << "survey:\n  start_time: \"2026-01-01T00:00:00Z\"\n";
  y << "  speed_m_s: " << fx(d.in(s.speed_m_s, kSpeed)) << "\n";
  y << "  altitude_m: " << fx(d.in(s.altitude_m, kAltitude)) << "\n";
  y << "  lines:\n    - {name: L1, waypoints: [{east_m: " << fx(-h * fe)
    << ", north_m: " << fx(-h * fn) << "}, {east_m: " << fx(h * fe) << ", north_m: " << fx(h * fn)
    << "}]}\n";
  y << "sonar:\n  preset: " << preset << "\n";
  if (s.range_m) y << "  range_m: " << fx(range_m) << "\n";
  if (s.samples) y << "  samples: " << *s.samples << "\n";
  y << "noise:\n  model: " << s.noise_model.names[d.pick(s.noise_model.weights, kNoiseModel)]
    << "\n  snr_db: " << fx(d.in(s.snr_db, kSnr), 2) << "\n";
  if (!s.labels_yaml.empty()) y << "output:\n  labels: " << s.labels_yaml << "\n";
  item.yaml = y.str();
  return item;
}

}  // namespace sonarsynth
