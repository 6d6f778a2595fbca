// SPDX-License-Identifier: MIT
// Simulation files (docs/scene-format.md): the run's sections beside the scene. The `survey`
// section is read in simulation_survey.cpp, effective.yaml written in effective_config.cpp.
#include "sonarsynth/formats/config/simulation_file.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <set>
#include <sstream>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/option_table.hpp"
#include "sonarsynth/formats/config/scene_file.hpp"
#include "sonarsynth/formats/config/simulation_file_parts.hpp"
#include "sonarsynth/formats/config/yaml_fields.hpp"
#include "sonarsynth/formats/io/utc_text.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "sonarsynth/sonar_presets.hpp"

namespace sonarsynth {
namespace simulation_file {

// Keys of one section: its declared options (formats/config/option_table.cpp) and `extra`
// sub-sections.
std::set<std::string> keys_of(std::string_view section, std::set<std::string> extra) {
  for (const options::Option* o : options::in_section(section)) extra.insert(std::string(o->key));
  return extra;
}

}  // namespace simulation_file

using namespace simulation_file;

namespace {

namespace fs = std::filesystem;

// sonar.vertical_beam: the keys of its shape only; a beam given without `shape` keeps the shape
// it had (gaussian, or a preset's). Keys left out keep the values of the beam it had (the
// default one or a preset's) if the shape stays, else VerticalBeamPattern's defaults.
void read_beam(const Fields& b, SimulationSetup& setup) {
  VerticalBeamPattern& v = setup.config.sonar.vertical_beam;
  const VerticalBeamShape before = v.shape;
  options::read(b, options::at("sonar.vertical_beam.shape"), setup);
  if (v.shape != before) {
    const VerticalBeamShape shape = v.shape;
    v = VerticalBeamPattern{};
    v.shape = shape;
  }
  switch (v.shape) {
    case VerticalBeamShape::uniform:
      b.only({"shape"});
      break;
    case VerticalBeamShape::gaussian:
      b.only({"shape", "width_deg"});
      options::read(b, options::at("sonar.vertical_beam.width_deg"), setup);
      break;
    case VerticalBeamShape::paper_sine_pair:
      b.only({"shape", "upper_half_width_deg", "lower_half_width_deg"});
      options::read(b, options::at("sonar.vertical_beam.upper_half_width_deg"), setup);
      options::read(b, options::at("sonar.vertical_beam.lower_half_width_deg"), setup);
      break;
    case VerticalBeamShape::sinc:
      b.only({"shape", "height_over_wavelength"});
      options::read(b, options::at("sonar.vertical_beam.height_over_wavelength"), setup);
      break;
    case VerticalBeamShape::table: {
      b.only({"shape", "off_axis_deg", "gain_db"});
      const YAML::Node a = b.node()["off_axis_deg"], g = b.node()["gain_db"];
      if (!a.IsSequence() || !g.IsSequence() || a.size() != g.size() || a.size() < 2) {
        b.fail("off_axis_deg", "off_axis_deg and gain_db must be lists of equal length >= 2");
      }
      v.table_off_axis_rad.clear();
      v.table_gain_db.clear();
      for (std::size_t i = 0; i < a.size(); ++i) {
        v.table_off_axis_rad.push_back(rad_from_deg(b.element_number("off_axis_deg", a[i], i)));
        v.table_gain_db.push_back(b.element_number("gain_db", g[i], i));
      }
      break;
    }
  }
  try {
    v.validate();
  } catch (const InputError& e) {
    b.fail("", e.what());
  }
}

// output.labels (docs/labels.md): coco, yolo, voc, chips (a boolean, or a map of its settings),
// segmentation, chip_color, chip_samples.
void read_labels(const Fields& f, LabelOutput& l, bool truth) {
  f.only({"coco", "yolo", "voc", "chips", "segmentation", "chip_color", "chip_samples"});
  l.coco = f.boolean("coco", l.coco);
  l.yolo = f.boolean("yolo", l.yolo);
  l.voc = f.boolean("voc", l.voc);
  if (f.given("segmentation")) {
    const std::string v = f.text("segmentation");
    if (v == "rle") {
      l.segmentation = LabelOutput::Segmentation::rle;
    } else if (v == "polygon") {
      l.segmentation = LabelOutput::Segmentation::polygon;
    } else if (v == "none") {
      l.segmentation = LabelOutput::Segmentation::none;
    } else {
      f.fail_value("segmentation", "one of rle, polygon, none");
    }
  }
  if (f.given("chip_color")) {
    const std::string v = f.text("chip_color");
    if (v == "colormap") {
      l.chip_color = LabelOutput::ChipColor::colormap;
    } else if (v == "grey") {
      l.chip_color = LabelOutput::ChipColor::grey;
    } else {
      f.fail_value("chip_color", "one of grey, colormap");
    }
  }
  if (f.given("chip_samples")) {
    const std::string v = f.text("chip_samples");
    if (v == "none") {
      l.chip_samples = LabelOutput::ChipSamples::none;
    } else if (v == "u16") {
      l.chip_samples = LabelOutput::ChipSamples::u16;
    } else if (v == "f32") {
      l.chip_samples = LabelOutput::ChipSamples::f32;
    } else {
      f.fail_value("chip_samples", "one of none, u16, f32");
    }
  }
  if (f.has("chips") && f.node()["chips"].IsMap()) {
    const Fields c = f.child("chips");
    c.only({"size_px", "stride_px", "max_nodata_fraction"});
    l.chips = true;
    const auto size = c.integer("size_px", static_cast<std::int64_t>(l.chip_size_px));
    if (size < 16 || size > 8192) c.fail_value("size_px", "16 <= size_px <= 8192");
    const auto stride = c.integer("stride_px", size);
    if (stride < 1 || stride > 8192) c.fail_value("stride_px", "1 <= stride_px <= 8192");
    l.chip_size_px = static_cast<std::size_t>(size);
    l.chip_stride_px = static_cast<std::size_t>(stride);
    l.chip_max_nodata_fraction = c.number("max_nodata_fraction", l.chip_max_nodata_fraction);
    if (!(l.chip_max_nodata_fraction >= 0.0 && l.chip_max_nodata_fraction < 1.0)) {
      c.fail_value("max_nodata_fraction", "0 <= max_nodata_fraction < 1");
    }
  } else {
    l.chips = f.boolean("chips", l.chips);
  }
  if (l.any() && !truth) {
    f.fail("", "labels need the truth (output.truth: true)");
  }
}

// A command-line override: the bounds of the option it overrides, the error naming the flag.
template <class T>
void check_override(const options::Option& o, T value) {
  if (!o.accepts(static_cast<double>(value))) {
    std::ostringstream v;
    v << std::setprecision(15) << value;  // "0", "1000000000", not "0.000000"
    throw InputError(std::string(o.flag->name) + " = " + v.str() +
                     ". Violated constraint: " + o.bounds() + " (as " + o.path() + ")");
  }
}

}  // namespace

UtcTime parse_utc(const std::string& text, const std::string& what) {
  int y = 0, mo = 0, d = 0, h = 0, mi = 0;
  double s = 0;
  char z = 0;
  if (std::sscanf(text.c_str(), "%d-%d-%dT%d:%d:%lf%c", &y, &mo, &d, &h, &mi, &s, &z) != 7 ||
      z != 'Z' || mo < 1 || mo > 12 || d < 1 || d > 31 || h < 0 || h > 23 || mi < 0 || mi > 59 ||
      !(s >= 0 && s < 60) || y < 1970 || y > 2100) {
    throw InputError(what + " = '" + text +
                     "'. Violated constraint: UTC time YYYY-MM-DDTHH:MM:SSZ, years 1970-2100");
  }
  const std::chrono::year_month_day ymd{std::chrono::year(y),
                                        std::chrono::month(static_cast<unsigned>(mo)),
                                        std::chrono::day(static_cast<unsigned>(d))};
  if (!ymd.ok()) throw InputError(what + " = '" + text + "': no such date");
  return std::chrono::sys_days(ymd) + std::chrono::hours(h) + std::chrono::minutes(mi) +
         std::chrono::microseconds(std::llround(s * 1e6));
}

std::string format_utc(UtcTime t) {
  return calendar::utc_text(t);
}

namespace yaml {
LabelOutput read_label_output(const Fields& f, bool truth) {
  LabelOutput l;
  read_labels(f, l, truth);
  return l;
}
}  // namespace yaml

namespace {

// output.formats: [xtf, jsf] (docs/scene-format.md), names of the format list that `simulate`
// writes; output.jsf (read before, from the option table) is the alias of listing jsf.
void read_output_formats(const Fields& f, SimulationSetup& setup) {
  const YAML::Node& n = f.node()["formats"];
  if (!n.IsSequence() || n.size() == 0) {
    f.fail_value("formats", "a non-empty list of sonar formats, e.g. [xtf, jsf] (one of " +
                                sonar_format_names() + ")");
  }
  std::vector<std::string> names;
  for (std::size_t i = 0; i < n.size(); ++i) {
    const std::string key = "formats[" + std::to_string(i) + "]";
    const std::string name = f.scalar_text(key, n[i]);
    const SonarFormat* format = find_sonar_format(name);
    const auto refuse = [&](const std::string& constraint) {
      throw InputError(f.file() + ": " + f.key_path(key) + " = '" + name +
                       "'. Violated constraint: " + constraint);
    };
    if (!format || !format->capabilities.simulate) {
      refuse("a sonar format simulate writes: one of " +
             sonar_format_names(&SonarFormatCapabilities::simulate));
    }
    if (std::find(names.begin(), names.end(), format->name) != names.end()) {
      refuse("each format once");
    }
    names.emplace_back(format->name);
  }
  if (f.given("jsf")) {
    const bool listed = std::find(names.begin(), names.end(), "jsf") != names.end();
    if (f.boolean("jsf", false) && !listed) names.emplace_back("jsf");
    if (!f.boolean("jsf", false) && listed) {
      f.fail_value("jsf",
                   "not false when output.formats lists jsf (output.jsf: true is the "
                   "alias of listing it)");
    }
  }
  setup.output_formats = std::move(names);
}

}  // namespace

bool SimulationSetup::writes_format(std::string_view name) const {
  return std::find(output_formats.begin(), output_formats.end(), name) != output_formats.end();
}

Survey SimulationSetup::make_survey() const {
  return Survey(lines, vehicle, config.sonar.effective_ping_period_s(), start_time, config.seed);
}

namespace {

// `sonar`: a preset, then the keys given beside it; --range and --samples override them.
void read_sonar_section(const Fields& top, const SimulationOverrides& overrides,
                        SimulationSetup& setup) {
  SonarConfig& s = setup.config.sonar;
  if (top.has("sonar")) {
    const Fields f = top.child("sonar");
    f.only(keys_of("sonar", {"preset", "vertical_beam", "pulse"}));
    // A preset first (docs/sonar-presets.md): every key given beside it wins, in any order.
    if (f.given("preset")) {
      const SonarPreset* p = find_sonar_preset(f.text("preset"));
      if (!p) f.fail_value("preset", "one of " + sonar_preset_names());
      s = p->sonar;
    }
    options::read_all(f, "sonar", setup);
    if (f.has("vertical_beam")) read_beam(f.child("vertical_beam"), setup);
    if (f.has("pulse")) {
      const Fields p = f.child("pulse");
      const SonarConfig::Pulse preset_pulse = s.pulse;
      options::read(p, options::at("sonar.pulse.type"), setup);
      const char* key = s.pulse == SonarConfig::Pulse::kCw ? "length_us" : "bandwidth_khz";
      p.only({"type", key});
      // A type other than the preset's (or the default's) carries no length or bandwidth of its
      // own: without the key the pulse would silently be one sample long (CW) or fail later.
      if (s.pulse != preset_pulse && !p.given(key)) {
        p.fail(key, std::string("is required when type is ") +
                        (s.pulse == SonarConfig::Pulse::kCw ? "cw" : "chirp") +
                        " and the preset's pulse is not");
      }
      options::read(p, options::at(std::string("sonar.pulse.") + key), setup);
    }
  }
  // Command-line overrides: the same bounds as the scene file's keys, named by the flag.
  if (overrides.range_m) {
    const options::Option& range = options::at("sonar.range_m");
    check_override(range, *overrides.range_m);
    s.max_range_m = *overrides.range_m;
    setup.range_key = range.flag->name;
  }
  if (overrides.samples) {
    check_override(options::at("sonar.samples"), *overrides.samples);
    s.samples_per_channel = *overrides.samples;
  }
  // A ping period shorter than the two-way travel time to the maximum range overlaps pings.
  if (const auto v = ping_period_violation(setup))
    top.child("sonar").fail_value("ping_period_s", *v);
}

// `render`: physics switches and quality; --quality overrides the quality.
void read_render_section(const Fields& top, const SimulationOverrides& overrides,
                         SimulationSetup& setup) {
  SimulationConfig& cfg = setup.config;
  if (top.has("render")) {
    const Fields f = top.child("render");
    f.only(keys_of("render", {"water", "quality"}));
    options::read_all(f, "render", setup);
    for (const char* sub : {"water", "quality"}) {
      if (!f.has(sub)) continue;
      const Fields w = f.child(sub);
      const std::string section = std::string("render.") + sub;
      w.only(keys_of(section));
      options::read_all(w, section, setup);
    }
  }
  if (overrides.quality && !cfg.quality.apply_preset(*overrides.quality)) {
    const options::Option& quality = options::at("render.quality.grid_subdivisions");
    throw InputError(std::string(quality.flag->name) + " = '" + *overrides.quality +
                     "'. Violated constraint: " + QualityConfig::kPresetNames);
  }
}

// `noise`.
void read_noise_section(const Fields& top, SimulationSetup& setup) {
  if (top.has("noise")) {
    const Fields f = top.child("noise");
    f.only(keys_of("noise"));
    if (f.given("uniform_variance") && f.given("uniform_half_width")) {
      f.fail("uniform_variance",
             "give uniform_variance (the paper's gamma: u ~ U(0, sqrt(12 gamma))) or "
             "uniform_half_width (u ~ U(-a, a)), not both");
    }
    options::read_all(f, "noise", setup);
  }
}

// `sensor`: the sensor effects.
void read_sensor_section(const Fields& top, SimulationSetup& setup) {
  if (top.has("sensor")) {
    const Fields f = top.child("sensor");
    f.only(keys_of("sensor"));
    options::read_all(f, "sensor", setup);
    // The library caps the ring-down at a tenth of the range; a file asking for more is refused.
    if (f.given("ring_down_m")) {
      if (const auto v = ring_down_violation(setup)) f.fail_value("ring_down_m", *v);
    }
  }
}

// `output`: scaling, formats, labels, the mosaic and the display window.
void read_output_section(const Fields& top, SimulationSetup& setup) {
  if (top.has("output")) {
    const Fields f = top.child("output");
    f.only(keys_of("output", {"labels", "display_window_db", "mosaic", "formats"}));
    options::read_all(f, "output", setup);
    if (f.has("formats")) read_output_formats(f, setup);
    if (const auto v = bag_truth_violation(setup)) f.fail_value("bag_truth", *v);
    if (f.has("labels")) read_labels(f.child("labels"), setup.labels, setup.config.truth);
    if (f.has("mosaic")) {
      const Fields m = f.child("mosaic");
      m.only(keys_of("output.mosaic"));
      options::read_all(m, "output.mosaic", setup);
    }
    if (f.has("display_window_db")) {
      const auto w = f.numbers("display_window_db", 2);
      if (!(w[0] < w[1]) || w[1] - w[0] > 200.0) {
        f.fail_value("display_window_db", "[lo, hi] with lo < hi <= lo + 200 (dB)");
      }
      if (setup.display_linear) {
        f.fail_value("display_window_db", "not with output.display: linear");
      }
      setup.display_window_db = std::pair<double, double>{w[0], w[1]};
    }
  }
}

// Common XTF readers take at most 8192 samples per channel: more only on request.
void check_sample_count(const Fields& top, const SimulationOverrides& overrides,
                        const SimulationSetup& setup) {
  const SonarConfig& s = setup.config.sonar;
  if (const auto v = sample_count_violation(setup)) {
    const std::string& c = *v;
    if (overrides.samples) {
      throw InputError(std::string(options::at("sonar.samples").flag->name) + " = " +
                       std::to_string(s.samples_per_channel) + ". Violated constraint: " + c);
    }
    top.child("sonar").fail_value("samples", c);
  }
}

// The simulation of the YAML document `doc` over the scene `loaded`; `path` names it in messages.
SimulationSetup build_simulation(Scene loaded, const YAML::Node& doc, const std::string& path,
                                 const fs::path& base_dir, const SimulationOverrides& overrides) {
  SimulationSetup setup{.scene = std::move(loaded)};
  const Fields top(doc, path, "");
  SimulationConfig& cfg = setup.config;
  options::read(top, options::at("seed"), setup);
  if (overrides.seed) cfg.seed = *overrides.seed;

  read_sonar_section(top, overrides, setup);
  read_render_section(top, overrides, setup);
  read_noise_section(top, setup);
  read_sensor_section(top, setup);
  read_output_section(top, setup);
  check_sample_count(top, overrides, setup);

  // Limits on the run (checked before rendering, formats/config/run_check.cpp).
  if (top.has("limits")) {
    const Fields f = top.child("limits");
    f.only(keys_of("limits"));
    options::read_all(f, "limits", setup);
  }
  cfg.threads = overrides.threads.value_or(0);

  read_survey_section(top.child("survey"), path, base_dir, setup);
  // --range and --samples passed check_override in read_sonar_section, within bounds that
  // SonarConfig's own (range > 0 and finite, 1-65535 samples) contain: an error here is the file's.
  wrap(top, [&] { cfg.validate(); });
  return setup;
}

// The scene options of a run: the --seed override reaches the generated bathymetry too.
SceneLoadOptions scene_options(const SimulationOverrides& overrides) {
  SceneLoadOptions o;
  o.seed = overrides.seed;
  return o;
}

}  // namespace

std::optional<std::string> ping_period_violation(const SimulationSetup& setup) {
  const SonarConfig& s = setup.config.sonar;
  const double two_way_s = 2.0 * s.max_range_m / s.sound_speed_m_s;
  if (!(s.ping_period_s > 0.0 && s.ping_period_s < two_way_s)) return std::nullopt;
  return "ping_period_s >= the two-way travel time 2 " + setup.range_key +
         " / sound_speed_m_s = " + std::to_string(two_way_s) + " s";
}

std::optional<std::string> ring_down_violation(const SimulationSetup& setup) {
  const double ring_down_m = setup.config.sensor.ring_down_m;
  const double cap_m = 0.1 * setup.config.sonar.max_range_m;
  if (!(std::isfinite(ring_down_m) && ring_down_m > cap_m)) return std::nullopt;
  return "ring_down_m <= a tenth of the range (" + std::to_string(cap_m) + " m)";
}

std::optional<std::string> sample_count_violation(const SimulationSetup& setup) {
  if (setup.config.sonar.samples_per_channel <= xtf::kMaxPortableSamples ||
      setup.allow_more_than_8192_samples) {
    return std::nullopt;
  }
  return "samples <= 8192, the most common XTF readers accept (set "
         "output.allow_more_than_8192_samples: true to write more)";
}

std::optional<std::string> bag_truth_violation(const SimulationSetup& setup) {
  if (!setup.bag_truth) return std::nullopt;
  if (!setup.config.truth) {
    return "output.truth: true (the truth topics carry the rendered truth; output.truth is false)";
  }
  if (!setup.writes_format("mcap") && !setup.writes_format("rosbag")) {
    return "mcap or rosbag in output.formats (the bags that carry the truth topics)";
  }
  return std::nullopt;
}

void check_cross_keys(const SimulationSetup& setup, const std::string& name) {
  const auto fail = [&](const std::string& key, const std::string& value,
                        const std::string& constraint) {
    throw InputError(name + ": " + key + " = " + value + ". Violated constraint: " + constraint);
  };
  const auto text = [](double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  };
  const SimulationConfig& c = setup.config;
  if (const auto v = ping_period_violation(setup)) {
    fail("sonar.ping_period_s", text(c.sonar.ping_period_s), *v);
  }
  if (c.sensor.ring_down_m != SensorConfig{}.ring_down_m) {
    if (const auto v = ring_down_violation(setup)) {
      fail("sensor.ring_down_m", text(c.sensor.ring_down_m), *v);
    }
  }
  if (const auto v = sample_count_violation(setup)) {
    fail("sonar.samples", std::to_string(c.sonar.samples_per_channel), *v);
  }
  if (const auto v = bag_truth_violation(setup)) fail("output.bag_truth", "true", *v);
}

SimulationSetup load_simulation(const std::string& path, const SimulationOverrides& overrides) {
  Scene scene = load_scene(path, scene_options(overrides));
  return yaml::with_file_errors(path, [&] {
    return build_simulation(std::move(scene), yaml::load_file(path), path,
                            fs::path(path).parent_path(), overrides);
  });
}

SimulationSetup load_simulation_from_string(const std::string& yaml_text, const std::string& name,
                                            const std::filesystem::path& base_dir,
                                            const SimulationOverrides& overrides) {
  Scene scene = load_scene_from_string(yaml_text, name, base_dir, scene_options(overrides));
  return yaml::with_file_errors(name, [&] {
    return build_simulation(std::move(scene), yaml::load_string(yaml_text, name), name, base_dir,
                            overrides);
  });
}

}  // namespace sonarsynth
