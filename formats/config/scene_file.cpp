// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/config/scene_file.hpp"

#include <gdal_priv.h>
#include <gdal_utils.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <span>

#include "sonarsynth/formats/config/mesh_file.hpp"
#include "sonarsynth/formats/config/scene_bathymetry.hpp"
#include "sonarsynth/formats/config/scene_objects.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/raster/gdal_util.hpp"
#include "sonarsynth/object_types.hpp"
#include "sonarsynth/formats/config/yaml_fields.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

using yaml::Fields;

using yaml::resolve_path;

// State shared while building one scene.
struct Builder {
  Scene& scene;
  fs::path base_dir;
  Eigen::Vector2d centre_xy_m;  // centre of the bathymetry grid, local frame
  std::set<std::int32_t> used_ids;
  std::int32_t next_id = 1;

  // A position: {lat_deg, lon_deg} or {east_m, north_m} (metres from the grid centre, grid axes).
  Eigen::Vector2d position(const Fields& f, const std::string& key) const {
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

  std::uint16_t material(const Fields& f, const char* fallback) const {
    const std::string name = f.text("material", fallback);
    try {
      return scene.materials.index_of(name);
    } catch (const InputError& e) {
      f.fail("material", e.what());
    }
  }

  std::int32_t take_id(const Fields& f) {
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

  void place(ObjectPrimitive p, const Fields& f, double clearance_m, double embed) {
    p.place_on_seabed(scene.bathymetry, clearance_m, embed, f.file() + ": " + f.path());
    scene.objects.add(std::move(p));
  }

  // The object's entry in the target list (Scene::object_records).
  void record(const Fields& o, std::int32_t id, const std::string& type,
              const Eigen::Vector2d& xy_m, double heading_rad, double clearance_m, double embed,
              const char* default_material) {
    scene.object_records.push_back({id, o.text("name", ""), type,
                                    o.text("material", default_material), xy_m, heading_rad,
                                    clearance_m, embed});
  }

  // The keys an entry of `t` takes (include/sonarsynth/object_types.hpp).
  static std::set<std::string> keys_of(std::span<const std::string_view> keys) {
    return {keys.begin(), keys.end()};
  }

  // Parameter `key` of `t`, checked against the table's bounds, with the table's message.
  static double param(const Fields& f, const ObjectType& t, const std::string& key,
                      double fallback = 0.0) {
    const ObjectParam& p = *t.param(key);
    const double v = f.number(key, fallback);
    if (!p.accepts(v)) f.fail_value(key, p.constraint());
    return v;
  }

  // The half sizes of a `size_m: [length, width, height]` list.
  static Eigen::Vector3d half_size(const Fields& f, const ObjectType& t) {
    const ObjectParam& p = *t.param("size_m");
    const auto s = f.numbers("size_m", 3);
    for (const double v : s) {
      if (!p.accepts(v)) f.fail_value("size_m", p.constraint());
    }
    return 0.5 * Eigen::Vector3d(s[0], s[1], s[2]);
  }

  // What every type reads before its own keys.
  struct Pose {
    double clearance_m, embed, heading_rad;
  };

  void add_object(const Fields& o) {
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

  // Boxes sharing one id (docs/scene-format.md "objects").
  void add_wreck(const Fields& o, const ObjectType& t, const Pose& pose) {
    const double heading = pose.heading_rad;
    const Eigen::Vector2d centre = position(o, "position");
    const std::uint16_t mat = material(o, t.default_material.data());
    const auto parts = o.sequence("parts");
    if (parts.empty()) o.fail("parts", "a wreck needs at least one part (a box)");
    const std::int32_t id = take_id(o);
    record(o, id, "wreck", centre, heading, pose.clearance_m, pose.embed,
           t.default_material.data());
    const Eigen::Vector2d fwd(std::sin(heading), std::cos(heading)), stbd(fwd.y(), -fwd.x());
    for (const Fields& part : parts) {
      part.only(keys_of(t.part_keys));
      const auto off =
          part.has("offset_m") ? part.numbers("offset_m", 2) : std::vector<double>{0, 0};
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

  // A target held off the seabed by a tether (not rendered): a sphere or a level horizontal
  // cylinder whose centre is height_m above the seabed under it.
  void add_moored(const Fields& o, const ObjectType& t) {
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

  // A triangle mesh from a file (docs/scene-format.md "mesh").
  void add_mesh(const Fields& o, const ObjectType& t, const Pose& pose) {
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
      if (!p.accepts(where.scale.x()) || !p.accepts(where.scale.y()) ||
          !p.accepts(where.scale.z())) {
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
    record(o, id, "mesh", where.position_xy_m, heading, clearance, embed,
           t.default_material.data());
    scene.objects.add(place_mesh(std::move(model.mesh), where, scene.bathymetry, id, fallback,
                                 o.file() + ": " + o.path() + " (" + path + ")"));
  }

  // Objects from a vector layer: each feature's attributes are read as the keys of an inline
  // object; a Point gives `position`, a LineString a pipe from its first to its last vertex.
  void add_object_layer(const Fields& f) {
    f.only({"file", "layer"});
    const std::string path = resolve_path(base_dir, f.text("file"));
    // Layers without a CRS are taken as longitude/latitude.
    gdal::VectorLayer v = gdal::open_vector_layer(path, f.text("layer", ""), 4326, true, "scene");
    OGRLayer* layer = v.layer;
    OGRCoordinateTransformation* ct = v.to_target.get();
    int index = 0;
    for (auto& feature : *layer) {
      YAML::Node node;
      for (const auto& field : *feature) {
        if (field.IsNull() || field.IsUnset()) continue;
        node[field.GetName()] = field.GetAsString();
      }
      // size_m may be given as "l,w,h" or "[l, w, h]"; turn it back into a list.
      if (node["size_m"].IsDefined()) {
        const std::string text = node["size_m"].Scalar();
        try {
          node["size_m"] =
              YAML::Load(text.find('[') == std::string::npos ? "[" + text + "]" : text);
        } catch (const YAML::Exception&) {
          throw InputError(path + " feature " + std::to_string(index) + ": size_m = '" + text +
                           "'. Violated constraint: \"l,w,h\" or \"[l, w, h]\"");
        }
      }
      OGRGeometry* geom = feature->GetGeometryRef();
      const std::string where = path + " feature " + std::to_string(index++);
      if (!geom) throw InputError(where + ": has no geometry");
      std::unique_ptr<OGRGeometry> g(geom->clone());
      if (ct && g->transform(ct) != OGRERR_NONE) {
        throw InputError(where + ": cannot transform its geometry to WGS 84");
      }
      auto latlon = [](double lon, double lat) {
        YAML::Node p;
        p["lat_deg"] = lat;
        p["lon_deg"] = lon;
        return p;
      };
      const auto type = wkbFlatten(g->getGeometryType());
      if (type == wkbPoint) {
        const auto* pt = g->toPoint();
        node["position"] = latlon(pt->getX(), pt->getY());
      } else if (type == wkbLineString) {
        const auto* ls = g->toLineString();
        if (ls->getNumPoints() < 2) throw InputError(where + ": a pipe line needs 2 points");
        node["start"] = latlon(ls->getX(0), ls->getY(0));
        node["end"] = latlon(ls->getX(ls->getNumPoints() - 1), ls->getY(ls->getNumPoints() - 1));
        if (!node["type"].IsDefined()) node["type"] = "pipe";
      } else {
        throw InputError(where + ": geometry " + OGRGeometryTypeToName(type) +
                         " is not supported (Point or LineString)");
      }
      add_object(Fields(node, path, "feature " + std::to_string(index - 1)));
    }
  }

  void add_polygon_rings(const std::vector<std::vector<Eigen::Vector2d>>& rings, std::uint16_t m) {
    MaterialPolygon poly;
    poly.rings = rings;
    poly.material = m;
    scene.material_map.add_polygon(std::move(poly));
  }

  void add_polygons(const Fields& f) {
    if (f.has("file")) {
      f.only({"file", "layer", "material", "material_field"});
      const std::string path = resolve_path(base_dir, f.text("file"));
      gdal::VectorLayer v =
          gdal::open_vector_layer(path, f.text("layer", ""), scene.frame.epsg(), false, "scene");
      OGRLayer* layer = v.layer;
      OGRCoordinateTransformation* ct = v.to_target.get();
      const std::string field = f.text("material_field", "");
      for (auto& feature : *layer) {
        std::uint16_t m = 0;
        if (!field.empty()) {
          const int idx = feature->GetFieldIndex(field.c_str());
          if (idx < 0) f.fail("material_field", "no field '" + field + "' in " + path);
          try {
            m = scene.materials.index_of(feature->GetFieldAsString(idx));
          } catch (const InputError& e) {
            throw InputError(path + " feature " + std::to_string(feature->GetFID()) + ": " +
                             e.what());
          }
        } else {
          m = material(f, "sand");
        }
        OGRGeometry* geom = feature->GetGeometryRef();
        if (!geom) continue;
        std::unique_ptr<OGRGeometry> g(geom->clone());
        if (g->transform(ct) != OGRERR_NONE)
          throw InputError(path + ": cannot transform a polygon");
        auto add_one = [&](const OGRPolygon* poly) {
          std::vector<std::vector<Eigen::Vector2d>> rings;
          for (const OGRLinearRing* ring : *poly) {
            std::vector<Eigen::Vector2d> r;
            for (const OGRPoint& pt : *ring) {
              if (!std::isfinite(pt.getX()) || !std::isfinite(pt.getY())) {
                throw InputError(path + " feature " + std::to_string(feature->GetFID()) +
                                 ": a polygon vertex is not a finite coordinate (" +
                                 std::to_string(pt.getX()) + ", " + std::to_string(pt.getY()) +
                                 ")");
              }
              r.push_back(scene.frame.local_from_projected({pt.getX(), pt.getY()}));
            }
            rings.push_back(std::move(r));
          }
          add_polygon_rings(rings, m);
        };
        const auto t = wkbFlatten(g->getGeometryType());
        if (t == wkbPolygon) {
          add_one(g->toPolygon());
        } else if (t == wkbMultiPolygon) {
          for (const OGRPolygon* p : *g->toMultiPolygon()) add_one(p);
        }
      }
      return;
    }
    f.only({"material", "coordinates_deg", "holes_deg"});
    const std::uint16_t m = material(f, "sand");
    auto ring = [&](const YAML::Node& seq, const std::string& key) {
      std::vector<Eigen::Vector2d> r;
      if (!seq.IsSequence() || seq.size() < 3)
        f.fail_value(key, "a list of at least 3 [lat, lon] pairs");
      std::size_t i = 0;
      for (const auto& pair : seq) {
        const std::string item = key + "[" + std::to_string(i++) + "]";
        if (!pair.IsSequence() || pair.size() != 2) f.fail_value(key, "[lat, lon] pairs");
        const double lat = f.element_number(item, pair[0], 0);
        const double lon = f.element_number(item, pair[1], 1);
        if (!(std::abs(lat) <= 90.0))
          f.fail(item, "latitude " + std::to_string(lat) + " beyond 90");
        try {
          r.push_back(scene.frame.local_from_geodetic({rad_from_deg(lat), rad_from_deg(lon), 0.0}));
        } catch (const InputError& e) {
          f.fail(item, e.what());
        }
      }
      return r;
    };
    std::vector<std::vector<Eigen::Vector2d>> rings{
        ring(f.node()["coordinates_deg"], "coordinates_deg")};
    if (f.has("holes_deg")) {
      if (!f.node()["holes_deg"].IsSequence()) f.fail_value("holes_deg", "a list of rings");
      for (const auto& h : f.node()["holes_deg"]) rings.push_back(ring(h, "holes_deg"));
    }
    add_polygon_rings(rings, m);
  }

  // A classification raster, warped (nearest neighbour) onto the scene's UTM zone.
  void set_classification(const Fields& f) {
    f.only({"file", "band", "classes"});
    const std::string path = resolve_path(base_dir, f.text("file"));
    gdal::DatasetPtr src = gdal::open_raster(path, "scene");
    const Fields classes = f.child("classes");
    std::map<long, std::uint16_t> lut;
    for (const auto& kv : classes.node()) {
      long value = 0;
      if (!kv.first.IsScalar() || !YAML::convert<long>::decode(kv.first, value))
        classes.fail(kv.first.Scalar(), "class values are integers");
      const std::string material = classes.scalar_text(kv.first.Scalar(), kv.second);
      try {
        lut[value] = scene.materials.index_of(material);
      } catch (const InputError& e) {
        classes.fail(kv.first.Scalar(), e.what());
      }
    }
    if (!src->GetSpatialRef())
      throw FormatError("scene: " + path + ": classification raster has no CRS");
    const int band_no = static_cast<int>(f.integer("band", 1));
    if (band_no < 1 || band_no > src->GetRasterCount()) f.fail_value("band", "an existing band");
    // Warp (nearest neighbour) onto the bathymetry's own nodes: classes line up with the DEM
    // cells whatever the raster's CRS and resolution.
    ClassRaster r;
    r.geometry = scene.bathymetry.geometry();
    const GridGeometry& g = r.geometry;
    const Eigen::Vector4d bb = scene.bathymetry.bounds();
    const Eigen::Vector2d lo =
        scene.frame.projected_from_local({bb[0] - 0.5 * g.dx_m, bb[1] - 0.5 * std::abs(g.dy_m)});
    const Eigen::Vector2d hi =
        scene.frame.projected_from_local({bb[2] + 0.5 * g.dx_m, bb[3] + 0.5 * std::abs(g.dy_m)});
    auto num = [](double v) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.17g", v);
      return std::string(buf);
    };
    const std::vector<std::string> args = {"-of",
                                           "MEM",
                                           "-t_srs",
                                           "EPSG:" + std::to_string(scene.frame.epsg()),
                                           "-r",
                                           "near",
                                           "-ot",
                                           "Int32",
                                           "-dstnodata",
                                           "-2147483648",
                                           "-te",
                                           num(lo.x()),
                                           num(lo.y()),
                                           num(hi.x()),
                                           num(hi.y()),
                                           "-ts",
                                           std::to_string(g.cols),
                                           std::to_string(g.rows)};
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    // The band, as an in-memory VRT (gdalwarp of GDAL 3.6 has no -b).
    const std::string band_arg = std::to_string(band_no);
    const char* tr_args[] = {"-of", "VRT", "-b", band_arg.c_str(), nullptr};
    GDALTranslateOptions* to = GDALTranslateOptionsNew(const_cast<char**>(tr_args), nullptr);
    gdal::DatasetPtr one_band(
        GDALDataset::FromHandle(GDALTranslate("", GDALDataset::ToHandle(src.get()), to, nullptr)));
    GDALTranslateOptionsFree(to);
    if (!one_band) throw FormatError("scene: " + path + ": cannot select band " + band_arg);
    GDALWarpAppOptions* wo = GDALWarpAppOptionsNew(argv.data(), nullptr);
    if (!wo) throw Error("scene: internal error: bad warp options: " + gdal::last_error_message());
    GDALDatasetH src_h = GDALDataset::ToHandle(one_band.get());
    int usage_error = 0;
    GDALDatasetH out = GDALWarp("", nullptr, 1, &src_h, wo, &usage_error);
    GDALWarpAppOptionsFree(wo);
    if (!out)
      throw FormatError("scene: " + path +
                        ": cannot warp the classification raster: " + gdal::last_error_message());
    gdal::DatasetPtr w(GDALDataset::FromHandle(out));
    std::vector<std::int32_t> values(g.size());
    if (w->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, w->GetRasterXSize(), w->GetRasterYSize(),
                                      values.data(), w->GetRasterXSize(), w->GetRasterYSize(),
                                      GDT_Int32, 0, 0) != CE_None) {
      throw FormatError("scene: " + path + ": cannot read: " + gdal::last_error_message());
    }
    // -te/-ts produce a north-up raster; flip rows if the DEM runs south-up.
    if (g.dy_m > 0) {
      for (std::size_t row = 0; row < g.rows / 2; ++row) {
        std::swap_ranges(values.begin() + static_cast<std::ptrdiff_t>(row * g.cols),
                         values.begin() + static_cast<std::ptrdiff_t>((row + 1) * g.cols),
                         values.begin() + static_cast<std::ptrdiff_t>((g.rows - 1 - row) * g.cols));
      }
    }
    r.classes.resize(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) {
      const auto it = lut.find(values[i]);
      r.classes[i] = it == lut.end() ? ClassRaster::kNoClass : it->second;
    }
    scene.material_map.set_raster(std::move(r));
  }
};

// The scene of the YAML document `doc`; `path` names it in messages.
Scene build_scene(const YAML::Node& doc, const std::string& path, const fs::path& base_dir,
                  const SceneLoadOptions& options) {
  const Fields top(doc, path, "");
  top.only({"name", "description", "seed", "bathymetry", "materials", "seabed", "objects", "survey",
            "sonar", "noise", "sensor", "render", "output", "limits", "derived"});

  // Bathymetry: from a raster (optionally refined), or generated (formats/config/scene_bathymetry.cpp).
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
