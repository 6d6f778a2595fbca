// SPDX-License-Identifier: MIT
// Simulation.set / get / sonarsynth.options(): every scalar option of a scene file through the
// single option table (formats/private/sonarsynth/formats/config/option_table.hpp), read from a
// one-key YAML map so that the checks and the messages are those of a scene file.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include "bindings.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/option_table.hpp"
#include "sonarsynth/formats/config/yaml_fields.hpp"
#include "sonarsynth/sonar_presets.hpp"

namespace sonarsynth::python {

YAML::Node yaml_value(const py::handle& value) {
  if (value.is_none()) return YAML::Node(YAML::NodeType::Null);
  if (py::isinstance<py::bool_>(value)) return YAML::Node(value.cast<bool>() ? "true" : "false");
  if (py::isinstance<py::str>(value)) return YAML::Node(value.cast<std::string>());
  if (py::hasattr(value, "__fspath__")) {  // os.PathLike: its path text
    return YAML::Node(py::module_::import("os").attr("fspath")(value).cast<std::string>());
  }
  const bool array = py::isinstance<py::array>(value) && value.cast<py::array>().ndim() > 0;
  if (!array && (py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value) ||
                 py::hasattr(value, "__float__"))) {
    // numpy scalars: their Python equivalent (item()) first.
    const py::object v = py::hasattr(value, "item") ? value.attr("item")()
                                                    : py::reinterpret_borrow<py::object>(value);
    return YAML::Node(py::repr(v).cast<std::string>());
  }
  if (py::isinstance<py::dict>(value)) {
    YAML::Node map(YAML::NodeType::Map);
    map.SetStyle(YAML::EmitterStyle::Flow);  // messages show {a: 1} as a file would
    for (const auto& [k, v] : value.cast<py::dict>()) {
      map[py::str(k).cast<std::string>()] = yaml_value(v);
    }
    return map;
  }
  if (py::isinstance<py::sequence>(value)) {
    YAML::Node seq(YAML::NodeType::Sequence);
    seq.SetStyle(YAML::EmitterStyle::Flow);  // messages show [1, 2] as a file would
    for (const py::handle item : value) seq.push_back(yaml_value(item));
    return seq;
  }
  throw InputError("cannot take a " + py::repr(py::type::of(value)).cast<std::string>() +
                   " as a scene-file value");
}

namespace {

// The keys a scene file accepts in `section` (as simulation_file.cpp's only() checks).
std::set<std::string> known_keys(const std::string& section) {
  std::set<std::string> keys;
  for (const options::Option& o : options::all()) {
    const std::string s(o.section);
    if (s == section) {
      keys.insert(std::string(o.key));
    } else if (s.size() > section.size() && s.compare(0, section.size() + (section.empty() ? 0 : 1),
                                                      section.empty() ? "" : section + ".") == 0) {
      const std::string rest = s.substr(section.empty() ? 0 : section.size() + 1);
      keys.insert(rest.substr(0, rest.find('.')));
    }
  }
  if (section == "sonar") keys.insert("preset");
  if (section == "survey") keys.insert({"start_time", "lever_arm_m"});
  return keys;
}

void set_one(PySimulation& s, const std::string& path, const py::handle& value) {
  const std::size_t dot = path.rfind('.');
  const std::string section = dot == std::string::npos ? "" : path.substr(0, dot);
  const std::string key = dot == std::string::npos ? path : path.substr(dot + 1);
  YAML::Node map(YAML::NodeType::Map);
  map[key] = yaml_value(value);
  const yaml::Fields f(map, s.name, section);
  yaml::with_file_errors(s.name, [&] {
    if (path == "sonar.preset") {
      const SonarPreset* p = find_sonar_preset(f.text(key));
      if (!p) f.fail_value(key, "one of " + sonar_preset_names());
      s.setup.config.sonar = p->sonar;
    } else if (path == "survey.start_time") {
      s.setup.start_time = parse_utc(f.text(key), s.name + ": survey.start_time");
    } else if (path == "survey.lever_arm_m") {
      const auto la = f.numbers(key, 3);
      s.setup.vehicle.lever_arm_m = {la[0], la[1], la[2]};
    } else {
      const options::Option* o = nullptr;
      try {
        o = &options::at(path);
      } catch (const std::out_of_range&) {
        f.only(known_keys(section));  // names the unknown key and the known ones
        throw InputError(s.name + ": " + path + ": not an option (sonarsynth.options())");
      }
      options::read(f, *o, s.setup);
    }
  });
  s.invalidate();
}

// Flattens {"sonar": {"range_m": 50}} and {"sonar.range_m": 50} alike, in the dict's order.
void set_dict(PySimulation& s, const std::string& prefix, const py::dict& d) {
  for (const auto& [k, v] : d) {
    const std::string path =
        prefix.empty() ? k.cast<std::string>() : prefix + "." + k.cast<std::string>();
    if (py::isinstance<py::dict>(v)) {
      set_dict(s, path, v.cast<py::dict>());
    } else {
      set_one(s, path, v);
    }
  }
}

py::object value_of(const options::Option& o, const SimulationSetup& setup) {
  if (o.kind == options::Kind::seed) return py::int_(options::seed_of(setup));
  const double v = o.get(setup);
  switch (o.kind) {
    case options::Kind::boolean:
      return py::bool_(v != 0.0);
    case options::Kind::choice:
      return py::str(std::string(o.choices[static_cast<std::size_t>(v)]));
    case options::Kind::integer:
      if (std::isnan(v)) return py::str(std::string(o.word));
      return py::int_(static_cast<long long>(v));
    default:
      if (std::isnan(v) && !o.word.empty()) return py::str(std::string(o.word));
      return py::float_(v);
  }
}

const char* kind_name(options::Kind k) {
  switch (k) {
    case options::Kind::real:
      return "real";
    case options::Kind::integer:
      return "integer";
    case options::Kind::boolean:
      return "boolean";
    case options::Kind::choice:
      return "choice";
    case options::Kind::seed:
      return "seed";
  }
  return "";
}

}  // namespace

void bind_options(py::module_& m, py::class_<PySimulation>& cls) {
  m.def(
      "options",
      [] {
        py::list out;
        for (const options::Option& o : options::all()) {
          py::dict d;
          d["path"] = o.path();
          d["unit"] = std::string(o.unit);
          d["kind"] = kind_name(o.kind);
          d["constraint"] =
              o.kind == options::Kind::choice ? std::string(o.choice_constraint) : o.bounds();
          py::list choices;
          for (const auto c : o.choices) choices.append(std::string(c));
          d["choices"] = choices;
          d["word"] = std::string(o.word);
          d["flag"] = o.flag ? std::string(o.flag->name) : std::string();
          out.append(d);
        }
        return out;
      },
      "Every scalar option of a scene file, in the order of docs/scene-format.md: a list of "
      "dicts with path ('sonar.range_m'), unit (the file's unit: 'm', 'deg', 'kHz', ...), "
      "kind (real, integer, boolean, choice, seed), constraint, choices, word (a word taken "
      "instead of a number, e.g. 'auto') and flag (the CLI override). Besides these, "
      "Simulation.set takes sonar.preset, survey.start_time and survey.lever_arm_m.");

  cls.def(
      "set",
      [](PySimulation& s, const std::string& path, const py::object& value) {
        set_one(s, path, value);
      },
      py::arg("path"), py::arg("value"),
      "Sets one option by its scene-file key path, in the file's unit: "
      "set('sonar.range_m', 50) (metres), set('sonar.tilt_deg', 20) (degrees), "
      "set('noise.model', 'paper'). Raises ValueError with the message a scene file holding "
      "the value would give.");
  cls.def(
      "set", [](PySimulation& s, const py::dict& values) { set_dict(s, "", values); },
      py::arg("values"),
      "Sets several options from a dict of key paths ({'sonar.range_m': 50}) or of nested "
      "sections ({'sonar': {'range_m': 50}}), in order.");
  cls.def(
      "get",
      [](const PySimulation& s, const std::string& path) -> py::object {
        if (path == "sonar.preset") throw InputError("sonar.preset is write-only");
        try {
          return value_of(options::at(path), s.setup);
        } catch (const std::out_of_range&) {
          throw InputError(path + ": not an option (sonarsynth.options())");
        }
      },
      py::arg("path"),
      "The value of an option in the scene file's unit (a choice by name, 'auto' for an "
      "automatic value).");
  cls.def(
      "settings",
      [](const PySimulation& s) {
        py::dict d;
        for (const options::Option& o : options::all()) d[py::str(o.path())] = value_of(o, s.setup);
        return d;
      },
      "Every option's current value: {key path: value}.");
}

}  // namespace sonarsynth::python
