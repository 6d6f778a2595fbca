// SPDX-License-Identifier: MIT
// The object types of a dataset spec (`objects.types`, docs/dataset.md): the ranges of each
// type's keys within the scene file's bounds, and the mesh models a spec names.
#include <algorithm>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <string_view>

#include "sonarsynth/formats/config/dataset_spec_parts.hpp"
#include "sonarsynth/formats/config/mesh_file.hpp"
#include "sonarsynth/object_types.hpp"

namespace sonarsynth::dataset_spec {
namespace {

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

// The copy of the model `file` in the dataset directory (docs/dataset.md): models/ and its file
// name, with _2, _3 ... before the extension when another model of the spec took that name.
std::string model_copy_name(const std::vector<std::string>& files,
                            const std::vector<std::string>& copies,
                            const std::filesystem::path& file) {
  for (std::size_t i = 0; i < copies.size(); ++i) {
    if (files[i] == file.string()) return copies[i];  // the same file named twice
  }
  const std::filesystem::path name = file.filename();
  for (int k = 1;; ++k) {
    const std::string copy = "models/" + (k == 1 ? name.string()
                                                 : name.stem().string() + "_" + std::to_string(k) +
                                                       name.extension().string());
    if (std::find(copies.begin(), copies.end(), copy) == copies.end()) return copy;
  }
}

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
    t.model_copies.push_back(model_copy_name(t.model_files, t.model_copies, file));
  }
  const ObjectType& mesh = *find_object_type("mesh");
  t.scale = read_object_range(d, mesh, mesh.spec_keys.front());
  check_scene_bound(d, "scale", t.scale, 3, "objects.scale");
}

}  // namespace

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

}  // namespace sonarsynth::dataset_spec
