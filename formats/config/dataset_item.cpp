// SPDX-License-Identifier: MIT
// Item k of a dataset (docs/dataset.md): its split, its seed and its scene file drawn from the
// spec with counter-based random numbers keyed by the item's seed.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string_view>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/dataset.hpp"
#include "sonarsynth/formats/config/dataset_spec_parts.hpp"
#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/object_types.hpp"
#include "sonarsynth/sonar_presets.hpp"

namespace sonarsynth {
namespace {

using namespace dataset_spec;

// Salt of the item seeds: keyed_hash(spec seed, index, kItemStream).
constexpr std::uint64_t kItemStream = 0x64617461'73657431ULL;  // "dataset1"

// The draw of spec key `key` of an object (ItemDraws sub-index 16 k + attribute).
ObjectAttribute attribute_of(std::string_view key) {
  return key == "diameter_m" ? kDiameter
         : key == "length_m" ? kLength
         : key == "width_m"  ? kWidth
         : key == "height_m" ? kHeight
                             : kScale;
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
  // As written into the dataset directory: each model named by its copy there, relative to
  // items/NNNNNN/ (docs/dataset.md), so that the directory can be moved.
  item.dataset_yaml = item.yaml;
  for (const DatasetObjectType& t : s.object_types) {
    for (std::size_t i = 0; i < t.model_copies.size(); ++i) {
      const std::string from = "file: " + yaml_quoted(t.model_files[i]);
      const std::string to = "file: " + yaml_quoted("../../" + t.model_copies[i]);
      for (std::size_t at = item.dataset_yaml.find(from); at != std::string::npos;
           at = item.dataset_yaml.find(from, at + to.size())) {
        item.dataset_yaml.replace(at, from.size(), to);
      }
    }
  }
  return item;
}

}  // namespace sonarsynth
