// SPDX-License-Identifier: MIT
// Dataset specs (docs/dataset.md): reading and validating the spec file. Its object types are
// read in dataset_spec_objects.cpp, the scene file's bounds on it checked in
// dataset_spec_bounds.cpp, and item k's scene drawn from it in dataset_item.cpp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <string_view>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/dataset.hpp"
#include "sonarsynth/formats/config/dataset_spec_parts.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"  // LabelOutput
#include "sonarsynth/formats/config/yaml_fields.hpp"
#include "sonarsynth/material.hpp"
#include "sonarsynth/object_types.hpp"
#include "sonarsynth/sonar_presets.hpp"

namespace sonarsynth {
namespace dataset_spec {

std::string number_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Fixed-point text: the scene file holds exactly the values the run uses.
std::string fx(double v, int decimals) {
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
                       double max, bool min_exclusive) {
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

namespace {

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

}  // namespace

// The highest value of knob `key`, or `fallback` (the scene's default) when it is left out.
double knob_hi(const DatasetSpec& s, const std::string& key, double fallback) {
  const auto it = s.knobs.find(key);
  return it == s.knobs.end() ? fallback : it->second.hi;
}

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// A name, a list of names or {name: weight}; every name must pass `valid` (else `valid_text`).
WeightedChoice read_choice(const Fields& f, const std::string& key, WeightedChoice fallback,
                           const std::function<bool(const std::string&)>& valid,
                           const std::string& valid_text) {
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

}  // namespace dataset_spec

namespace {

using namespace dataset_spec;

// The spec's `location`: the grid centre.
void read_location_section(const Fields& l, DatasetSpec& s) {
  l.only({"lat_deg", "lon_deg"});
  s.lat_deg = l.number_in("lat_deg", s.lat_deg, -80.0, 84.0);
  s.lon_deg = l.number_in("lon_deg", s.lon_deg, -180.0, 180.0);
}

// The spec's `seabed`: depth, grid cell, material, slope, roughness and ripples.
void read_seabed_section(const Fields& b, DatasetSpec& s) {
  b.only(
      with_knobs({"depth_m", "cell_m", "material", "slope_deg", "roughness", "ripples"}, "seabed"));
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

// The spec's `survey`: the line, altitude, speed and the sensor's motion.
void read_survey_section(const Fields& v, DatasetSpec& s) {
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

// The spec's `sonar`: the presets an item draws, its range and samples.
void read_sonar_section(const Fields& v, DatasetSpec& s) {
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

// The spec's `noise`: the noise model and its SNR.
void read_noise_section(const Fields& v, DatasetSpec& s) {
  v.only({"model", "snr_db"});
  s.noise_model = read_choice(
      v, "model", s.noise_model,
      [](const std::string& n) { return n == "none" || n == "paper" || n == "speckle"; },
      "none, paper, speckle");
  s.snr_db = read_range(v, "snr_db", s.snr_db, -100.0, 200.0);
  check_scene_bound(v, "snr_db", s.snr_db, 2, "noise.snr_db");
}

// The spec's `output`: the gain knobs.
void read_output_section(const Fields& v, DatasetSpec& s) {
  v.only(with_knobs({}, "output"));
  if (v.given("gain_db") && v.given("seabed_median_dbfs")) {
    v.fail("gain_db",
           "give gain_db (a fixed gain) or seabed_median_dbfs (the automatic gain's target), "
           "not both: a fixed gain ignores the target (docs/scene-format.md)");
  }
  read_knobs(v, "output", s);
}

// The spec's `objects`: how many, where, and the types drawn (`max_range_m`: the farthest range an
// item may have).
void read_objects_section(const Fields& o, DatasetSpec& s, double max_range_m) {
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

// The spec's `run`: quality, products, split and display window.
void read_run_section(const Fields& r, DatasetSpec& s) {
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

  if (top.has("location")) read_location_section(top.child("location"), s);
  if (top.has("seabed")) read_seabed_section(top.child("seabed"), s);
  if (top.has("survey")) read_survey_section(top.child("survey"), s);
  if (top.has("sonar")) read_sonar_section(top.child("sonar"), s);
  if (top.has("noise")) read_noise_section(top.child("noise"), s);
  if (top.has("output")) read_output_section(top.child("output"), s);
  double max_range_m = 0.0;
  for (const std::string& p : s.sonar_preset.names) {
    max_range_m = std::max(max_range_m, find_sonar_preset(p)->sonar.max_range_m);
  }
  if (s.range_m) max_range_m = s.range_m->hi;

  if (top.has("objects")) read_objects_section(top.child("objects"), s, max_range_m);
  check_item_constraints(s);
  if (top.has("run")) read_run_section(top.child("run"), s);
  YAML::Node without_count = YAML::Clone(root);
  without_count.remove("count");
  YAML::Emitter e;
  e << without_count;
  s.identity = e.c_str();
  return s;
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

}  // namespace sonarsynth
