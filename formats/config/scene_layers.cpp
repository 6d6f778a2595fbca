// SPDX-License-Identifier: MIT
// The seabed's material polygons and classification raster and the object layers of a scene file
// (docs/scene-format.md "seabed", "objects"), read from vector and raster files through GDAL.
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/scene_builder.hpp"
#include "sonarsynth/formats/raster/gdal_util.hpp"

namespace sonarsynth::scene_reader {

using yaml::resolve_path;

void Builder::add_object_layer(const Fields& f) {
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
        node["size_m"] = YAML::Load(text.find('[') == std::string::npos ? "[" + text + "]" : text);
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

void Builder::add_polygon_rings(const std::vector<std::vector<Eigen::Vector2d>>& rings,
                                std::uint16_t m) {
  MaterialPolygon poly;
  poly.rings = rings;
  poly.material = m;
  scene.material_map.add_polygon(std::move(poly));
}

void Builder::add_polygons(const Fields& f) {
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
      if (g->transform(ct) != OGRERR_NONE) throw InputError(path + ": cannot transform a polygon");
      auto add_one = [&](const OGRPolygon* poly) {
        std::vector<std::vector<Eigen::Vector2d>> rings;
        for (const OGRLinearRing* ring : *poly) {
          std::vector<Eigen::Vector2d> r;
          for (const OGRPoint& pt : *ring) {
            if (!std::isfinite(pt.getX()) || !std::isfinite(pt.getY())) {
              throw InputError(path + " feature " + std::to_string(feature->GetFID()) +
                               ": a polygon vertex is not a finite coordinate (" +
                               std::to_string(pt.getX()) + ", " + std::to_string(pt.getY()) + ")");
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
      if (!(std::abs(lat) <= 90.0)) f.fail(item, "latitude " + std::to_string(lat) + " beyond 90");
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

void Builder::set_classification(const Fields& f) {
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

}  // namespace sonarsynth::scene_reader
