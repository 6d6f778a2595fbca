// SPDX-License-Identifier: MIT
// The object vocabulary (include/sonarsynth/object_types.hpp) as Python sees it.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>

#include "bindings.hpp"
#include "sonarsynth/object_types.hpp"

namespace sonarsynth::python {
namespace {

py::dict param_dict(const ObjectParam& p) {
  py::dict d;
  d["key"] = std::string(p.key);
  d["unit"] = std::string(p.unit);
  d["lo"] = p.lo;
  d["hi"] = p.hi;
  d["lo_open"] = p.lo_open;
  d["constraint"] = p.constraint();
  return d;
}

py::dict type_dict(const ObjectType& t) {
  py::dict d;
  d["name"] = std::string(t.name);
  d["shape"] = std::string(to_string(t.shape));
  d["default_material"] = std::string(t.default_material);
  py::list keys, params, spec_keys;
  for (const std::string_view k : t.keys) keys.append(std::string(k));
  for (const ObjectParam& p : t.params) params.append(param_dict(p));
  for (const ObjectParam& p : object_common_params()) {
    if (t.takes(p.key) || (p.key == "lift_m" && !t.part_keys.empty())) params.append(param_dict(p));
  }
  for (const ObjectSpecKey& k : t.spec_keys) {
    py::dict s;
    s["key"] = std::string(k.key);
    s["param"] = std::string(k.param);
    s["default"] = k.spec_default;
    spec_keys.append(s);
  }
  d["keys"] = keys;
  d["params"] = params;
  d["dataset_spec_keys"] = spec_keys;
  d["example"] = std::string(t.example);
  return d;
}

}  // namespace

void bind_object_types(py::module_& m) {
  m.def(
      "object_types",
      []() {
        py::list out;
        for (const ObjectType& t : object_types()) out.append(type_dict(t));
        return out;
      },
      "The object types of scene files, dataset specs and add_object, from the one table all "
      "three read (docs/scene-format.md \"objects\"): a list of dicts with name, shape (the "
      "renderer's primitive), default_material, keys (every key its entry takes), params (key, "
      "unit, lo, hi, lo_open and constraint, the text of the message a value outside gets), "
      "dataset_spec_keys (the keys of objects.types.<name> with their defaults; empty where a "
      "spec cannot draw it) and example (a valid entry, flow YAML; files relative to samples/).");
}

}  // namespace sonarsynth::python
