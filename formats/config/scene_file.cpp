// SPDX-License-Identifier: MIT
// Scene files (docs/scene-format.md): bathymetry, materials and objects. The seabed's polygons,
// classification raster and object layers are read in scene_layers.cpp.
#include "sonarsynth/formats/config/scene_file.hpp"

#include <cmath>
#include <filesystem>
#include <set>
#include <span>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/mesh_file.hpp"
#include "sonarsynth/formats/config/scene_bathymetry.hpp"
#include "sonarsynth/formats/config/scene_builder.hpp"
#include "sonarsynth/formats/config/scene_objects.hpp"
#include "sonarsynth/formats/config/yaml_fields.hpp"
#include "sonarsynth/object_types.hpp"

namespace sonarsynth {
namespace scene_reader {

using yaml::resolve_path;

Eigen::Vector2d Builder::position(const Fields& f, const std::string& key) const {
  const Fields p = f.child(key);
  p.only({"lat_deg", "lon_deg", "east_m", "north_m"});
  if (p.node()["lat_deg"].IsDefined() || p.node()["lon_deg"].IsDefined()) {
    // Both are required: a null or missing one is not taken as 0.
    if (!p.has("lat_deg") || !p.has("lon_deg")) {
      p.fail(p.has("lat_deg") ? "lon_deg" : "lat_deg",
             "missing or null (a position needs both lat_deg and lon_deg)");
    }
    const double lat = p.number_in("lat_deg", 0.0, -90.0, 90.0);
    const double lon = p.number_in("lon_deg", 0.0, -180.0, 360.0);
    try {
      return scene.frame.local_from_geodetic({rad_from_deg(lat), rad_from_deg(lon), 0.0});
    } catch (const InputError& e) {
      p.fail("", e.what());
    }
  }
  return centre_xy_m + Eigen::Vector2d(p.number("east_m"), p.number("north_m"));
}

std::uint16_t Builder::material(const Fields& f, const char* fallback) const {
  const std::string name = f.text("material", fallback);
  try {
    return scene.materials.index_of(name);
  } catch (const InputError& e) {
    f.fail("material", e.what());
  }
}

std::int32_t Builder::take_id(const Fields& f) {
  std::int32_t id = next_id;
  if (f.has("id")) {
    const auto v = f.integer("id", 0);
    if (v <= 0 || v > 2'000'000'000) f.fail_value("id", "1 <= id <= 2e9");
    id = static_cast<std::int32_t>(v);
    if (used_ids.count(id)) f.fail_value("id", "ids are unique within a scene");
  }
  while (used_ids.count(id)) ++id;
  used_ids.insert(id);
  next_id = std::max(next_id, id + 1);
  return id;
}

void Builder::place(ObjectPrimitive p, const Fields& f, double clearance_m, double embed) {
  p.place_on_seabed(scene.bathymetry, clearance_m, embed, f.file() + ": " + f.path());
  scene.objects.add(std::move(p));
}

void Builder::record(const Fields& o, std::int32_t id, const std::string& type,
                     const Eigen::Vector2d& xy_m, double heading_rad, double clearance_m,
                     double embed, const char* default_material) {
  scene.object_records.push_back({id, o.text("name", ""), type,
                                  o.text("material", default_material), xy_m, heading_rad,
                                  clearance_m, embed});
}

std::set<std::string> Builder::keys_of(std::span<const std::string_view> keys) {
  return {keys.begin(), keys.end()};
}

double Builder::param(const Fields& f, const ObjectType& t, const std::string& key,
                      double fallback) {
  const ObjectParam& p = *t.param(key);
  const double v = f.number(key, fallback);
  if (!p.accepts(v)) f.fail_value(key, p.constraint());
  return v;
}

Eigen::Vector3d Builder::half_size(const Fields& f, const ObjectType& t) {
  const ObjectParam& p = *t.param("size_m");
  const auto s = f.numbers("size_m", 3);
  for (const double v : s) {
    if (!p.accepts(v)) f.fail_value("size_m", p.constraint());
  }
  return 0.5 * Eigen::Vector3d(s[0], s[1], s[2]);
}

void Builder::add_object(const Fields& o) {
  const std::string type = o.text("type");
  const ObjectType* t = find_object_type(type);
  const ObjectType& any = t ? *t : object_types().front();
  const Pose pose{param(o, any, "clearance_m"), param(o, any, "embed"),
                  rad_from_deg(o.number("heading_deg", 0.0))};
  if (!t) o.fail_value("type", "one of " + object_type_names());
  if (t->name == "mesh") return add_mesh(o, *t, pose);
  o.only(keys_of(t->keys));
  if (t->name == "wreck") return add_wreck(o, *t, pose);
  if (t->name == "moored") return add_moored(o, *t);
  ObjectPrimitive p;
  p.shape = t->shape;
  p.material = material(o, t->default_material.data());
  if (t->shape == ObjectShape::kCylinder) {  // pipe, cylinder
    const double radius = 0.5 * param(o, *t, "diameter_m");
    if (o.has("start") || o.has("end")) {
      const Eigen::Vector2d a = position(o, "start"), b = position(o, "end");
      const Eigen::Vector2d d = b - a;
      if (d.norm() <= 0.0) o.fail("end", "equals start: a pipe needs a length");
      p.centre_xy_m = 0.5 * (a + b);
      p.heading_rad = std::atan2(d.x(), d.y());
      p.half_extent_m = {0.5 * d.norm(), radius, radius};
    } else {
      p.centre_xy_m = position(o, "position");
      p.heading_rad = pose.heading_rad;
      p.half_extent_m = {0.5 * param(o, *t, "length_m"), radius, radius};
    }
  } else {  // box, rock
    p.centre_xy_m = position(o, "position");
    p.heading_rad = pose.heading_rad;
    if (t->param("diameter_m") && o.has("diameter_m")) {
      const double r = 0.5 * param(o, *t, "diameter_m");
      p.half_extent_m = {r, r, r};
    } else {
      p.half_extent_m = half_size(o, *t);
    }
  }
  p.id = take_id(o);
  record(o, p.id, type, p.centre_xy_m, p.heading_rad, pose.clearance_m, pose.embed,
         t->default_material.data());
  place(p, o, pose.clearance_m, pose.embed);
}

void Builder::add_wreck(const Fields& o, const ObjectType& t, const Pose& pose) {
  const double heading = pose.heading_rad;
  const Eigen::Vector2d centre = position(o, "position");
  const std::uint16_t mat = material(o, t.default_material.data());
  const auto parts = o.sequence("parts");
  if (parts.empty()) o.fail("parts", "a wreck needs at least one part (a box)");
  const std::int32_t id = take_id(o);
  record(o, id, "wreck", centre, heading, pose.clearance_m, pose.embed, t.default_material.data());
  const Eigen::Vector2d fwd(std::sin(heading), std::cos(heading)), stbd(fwd.y(), -fwd.x());
  for (const Fields& part : parts) {
    part.only(keys_of(t.part_keys));
    const auto off = part.has("offset_m") ? part.numbers("offset_m", 2) : std::vector<double>{0, 0};
    ObjectPrimitive b;
    b.half_extent_m = half_size(part, t);
    b.shape = t.shape;
    b.id = id;
    b.material = mat;
    b.centre_xy_m = centre + off[0] * fwd + off[1] * stbd;
    b.heading_rad = heading + rad_from_deg(part.number("heading_deg", 0.0));
    place(b, part, pose.clearance_m + param(part, t, "lift_m"), pose.embed);
  }
}

void Builder::add_moored(const Fields& o, const ObjectType& t) {
  ObjectPrimitive p;
  const std::string shape = o.text("shape", "sphere");
  const double radius = 0.5 * param(o, t, "diameter_m");
  const double height = param(o, t, "height_m");
  if (!(height > radius)) {
    o.fail_value("height_m", "height_m > diameter_m / 2 (the target is off the seabed)");
  }
  p.material = material(o, t.default_material.data());
  p.centre_xy_m = position(o, "position");
  p.heading_rad = rad_from_deg(o.number("heading_deg", 0.0));
  if (shape == "sphere") {
    if (o.has("length_m")) o.fail("length_m", "a sphere has no length_m");
    p.shape = ObjectShape::kEllipsoid;
    p.half_extent_m = {radius, radius, radius};
  } else if (shape == "cylinder") {
    p.shape = ObjectShape::kCylinder;
    p.half_extent_m = {0.5 * param(o, t, "length_m"), radius, radius};
  } else {
    o.fail_value("shape", "sphere or cylinder");
  }
  p.id = take_id(o);
  record(o, p.id, "moored", p.centre_xy_m, p.heading_rad, height - radius, 0.0,
         t.default_material.data());
  p.place_on_seabed(scene.bathymetry, height - radius, 0.0, o.file() + ": " + o.path());
  if (p.shape == ObjectShape::kCylinder) {  // level, not draped: the seabed under its centre
    p.base_z_m = {static_cast<float>(p.base_at(0.0))};
    p.base_step_m = 0.0;
  }
  scene.objects.add(std::move(p));
}

void Builder::add_mesh(const Fields& o, const ObjectType& t, const Pose& pose) {
  o.only(keys_of(t.keys));
  const double heading = pose.heading_rad, clearance = pose.clearance_m, embed = pose.embed;
  const std::string path = resolve_path(base_dir, o.text("file"));
  const std::string up = o.text("up_axis", "z");
  if (up != "z" && up != "y") o.fail_value("up_axis", "z or y");
  MeshPlacement where;
  where.position_xy_m = position(o, "position");
  where.heading_rad = heading;
  where.clearance_m = clearance;
  where.embed_fraction = embed;
  if (o.has("scale")) {
    if (o.node()["scale"].IsSequence()) {
      const auto v = o.numbers("scale", 3);
      where.scale = {v[0], v[1], v[2]};
    } else {
      const double v = o.number("scale");
      where.scale = {v, v, v};
    }
    const ObjectParam& p = *t.param("scale");
    if (!p.accepts(where.scale.x()) || !p.accepts(where.scale.y()) || !p.accepts(where.scale.z())) {
      o.fail_value("scale", p.constraint());
    }
  }
  const std::uint16_t fallback = material(o, t.default_material.data());
  mesh_file::Model model;
  try {
    model = mesh_file::load(path, up == "y");
  } catch (const InputError& e) {
    o.fail("file", e.what());
  }
  // The file's materials -> scene materials: by the file's material name or index.
  std::vector<std::uint16_t> lut(model.material_names.size(), fallback);
  if (o.has("face_materials")) {
    const Fields fm = o.child("face_materials");
    if (!fm.node().IsMap()) o.fail_value("face_materials", "a map {file material: material}");
    for (const auto& kv : fm.node()) {
      const std::string k = fm.scalar_text("face_materials", kv.first);
      std::size_t idx = model.material_names.size();
      for (std::size_t i = 0; i < model.material_names.size(); ++i) {
        if (model.material_names[i] == k) idx = i;
      }
      if (idx == model.material_names.size() && !k.empty() &&
          std::all_of(k.begin(), k.end(), [](char c) { return c >= '0' && c <= '9'; }) &&
          k.size() < 6) {
        idx = std::stoul(k);
      }
      if (idx >= model.material_names.size()) {
        std::string names;
        for (const auto& n : model.material_names) names += (names.empty() ? "" : ", ") + n;
        fm.fail(k, "no material '" + k + "' in " + path + " (it has: " + names +
                       "; or give an index below " + std::to_string(model.material_names.size()) +
                       ")");
      }
      try {
        lut[idx] = scene.materials.index_of(fm.scalar_text(k, kv.second));
      } catch (const InputError& e) {
        fm.fail(k, e.what());
      }
    }
  }
  for (auto& m : model.mesh.material) m = m < lut.size() ? lut[m] : fallback;
  const std::int32_t id = take_id(o);
  record(o, id, "mesh", where.position_xy_m, heading, clearance, embed, t.default_material.data());
  scene.objects.add(place_mesh(std::move(model.mesh), where, scene.bathymetry, id, fallback,
                               o.file() + ": " + o.path() + " (" + path + ")"));
}

}  // namespace scene_reader

namespace {

namespace fs = std::filesystem;
using scene_reader::Builder;
using yaml::Fields;

// The scene of the YAML document `doc`; `path` names it in messages.
Scene build_scene(const YAML::Node& doc, const std::string& path, const fs::path& base_dir,
                  const SceneLoadOptions& options) {
  const Fields top(doc, path, "");
  top.only({"name", "description", "seed", "bathymetry", "materials", "seabed", "objects", "survey",
            "sonar", "noise", "sensor", "render", "output", "limits", "derived"});

  // Bathymetry: from a raster (optionally refined), or generated
  // (formats/config/scene_bathymetry.cpp).
  std::optional<Scene> built(scene_bathymetry::load(top, path, base_dir, options));
  Scene& scene = *built;
  scene.name = top.text("name", fs::path(path).stem().string());
  Builder builder{scene, base_dir, scene.bathymetry.centre_xy_m(), {}, 1};

  // Materials: the built-in table, overridden or extended.
  for (const Fields& m : top.sequence("materials")) {
    m.only({"name", "lambert_mu_db", "reflectivity", "texture_shape", "roughness_rms_m",
            "roughness_length_m", "specular_reflection_db", "specular_rms_slope"});
    const std::string name = m.text("name");
    Material mat = scene.materials.contains(name) ? scene.materials[scene.materials.index_of(name)]
                                                  : Material{.name = name};
    if (m.has("lambert_mu_db"))
      mat.lambert_mu = std::pow(10.0, m.number_in("lambert_mu_db", 0, -100, 0) / 10.0);
    mat.paper_reflectivity = m.number_in("reflectivity", mat.paper_reflectivity, 0.0, 1.0);
    mat.texture_shape_nu = m.number_in("texture_shape", mat.texture_shape_nu, 0.0, 1e6);
    mat.roughness_rms_m = m.number_in("roughness_rms_m", mat.roughness_rms_m, 0.0, 10.0);
    mat.roughness_length_m = m.number_in("roughness_length_m", mat.roughness_length_m, 1e-4, 1e3);
    // The glint lobe (docs/physics.md §1.11): 10 log10(rho), or off.
    if (m.given("specular_reflection_db")) {
      mat.specular_rho =
          m.text("specular_reflection_db") == "off"
              ? 0.0
              : std::pow(10.0, m.number_in("specular_reflection_db", 0, -100, 0) / 10.0);
    }
    mat.specular_rms_slope =
        m.number_in("specular_rms_slope", mat.specular_rms_slope, 0.0, 1.0, true);
    scene.materials.set(mat);
  }

  // Seabed materials.
  scene.material_map = MaterialMap(scene.materials.index_of("sand"));
  if (top.has("seabed")) {
    const Fields s = top.child("seabed");
    s.only({"material", "classification", "polygons"});
    scene.material_map.set_default(builder.material(s, "sand"));
    if (s.has("classification")) builder.set_classification(s.child("classification"));
    for (const Fields& p : s.sequence("polygons")) builder.add_polygons(p);
  }

  // Objects.
  for (const Fields& o : top.sequence("objects")) {
    if (o.has("file") && o.text("type", "") != "mesh") {  // a vector layer of objects
      builder.add_object_layer(o);
    } else {
      builder.add_object(o);
    }
  }
  scene.objects.build_index();
  return std::move(*built);
}

}  // namespace

void add_scene_object(Scene& scene, const yaml::Fields& entry, const fs::path& base_dir) {
  const Eigen::Vector4d bb = scene.bathymetry.bounds();
  Builder builder{scene, base_dir, {0.5 * (bb[0] + bb[2]), 0.5 * (bb[1] + bb[3])}, {}, 1};
  for (const ObjectPrimitive& p : scene.objects.primitives()) builder.used_ids.insert(p.id);
  for (const ObjectRecord& r : scene.object_records) builder.used_ids.insert(r.id);
  // As in a file: the next automatic id is one above the largest taken so far.
  if (!builder.used_ids.empty()) builder.next_id = *builder.used_ids.rbegin() + 1;
  // A refused entry (a wreck's third part, a layer's fifth feature) leaves the objects as they
  // were.
  ObjectSet objects = scene.objects;
  std::vector<ObjectRecord> records = scene.object_records;
  try {
    yaml::with_file_errors(entry.file(), [&] {
      if (entry.has("file") && entry.text("type", "") != "mesh") {
        builder.add_object_layer(entry);
      } else {
        builder.add_object(entry);
      }
    });
  } catch (...) {
    scene.objects = std::move(objects);
    scene.object_records = std::move(records);
    throw;
  }
  scene.objects.build_index();
}

Scene load_scene(const std::string& path, const SceneLoadOptions& options) {
  return yaml::with_file_errors(path, [&] {
    return build_scene(yaml::load_file(path), path, fs::path(path).parent_path(), options);
  });
}

Scene load_scene_from_string(const std::string& yaml_text, const std::string& name,
                             const fs::path& base_dir, const SceneLoadOptions& options) {
  return yaml::with_file_errors(name, [&] {
    return build_scene(yaml::load_string(yaml_text, name), name, base_dir, options);
  });
}

}  // namespace sonarsynth
