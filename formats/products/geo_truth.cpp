// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/products/geo_truth.hpp"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <sstream>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/atomic_file.hpp"
#include "sonarsynth/formats/io/utc_text.hpp"
#include "sonarsynth/formats/raster/gdal_util.hpp"

namespace sonarsynth::geo_truth {
namespace {

constexpr const char* kWho = "truth vectors";
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Near and far seabed points of one ping side (local frame), or none.
struct Edge {
  Eigen::Vector2d near_xy, far_xy;
};

std::optional<Edge> seabed_edge(const SideOutput& s) {
  const std::size_t n = std::min(s.truth_class.size(), s.truth_ground_range_m.size());
  auto seabed = [&](std::size_t i) {
    return (s.truth_class[i] == SampleClass::seabed || s.truth_class[i] == SampleClass::object) &&
           s.truth_ground_xy(i).allFinite();
  };
  std::size_t first = n, last = n;
  for (std::size_t i = 0; i < n; ++i) {
    if (seabed(i)) {
      first = i;
      break;
    }
  }
  if (first == n) return std::nullopt;
  for (std::size_t i = n; i-- > first;) {
    if (seabed(i)) {
      last = i;
      break;
    }
  }
  return Edge{s.truth_ground_xy(first), s.truth_ground_xy(last)};
}

OGRSpatialReference wgs84() {
  OGRSpatialReference srs;
  srs.importFromEPSG(4326);
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  return srs;
}

/// A GeoJSON file being written: the dataset on the temporary path of `out`, one layer.
struct VectorFile {
  AtomicOutput out;
  gdal::DatasetPtr ds;
  OGRLayer* layer = nullptr;
  VectorFile(const std::filesystem::path& path, bool overwrite, const char* layer_name,
             OGRwkbGeometryType type)
      : out(path, overwrite) {
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GeoJSON");
    if (!drv) throw FormatError(std::string(kWho) + ": GDAL has no GeoJSON driver");
    CPLErrorReset();
    ds.reset(drv->Create(out.temp_path().string().c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    if (!ds) fail("cannot create the file");
    OGRSpatialReference srs = wgs84();
    layer = ds->CreateLayer(layer_name, &srs, type, nullptr);
    if (!layer) fail("cannot create the layer");
  }
  [[noreturn]] void fail(const std::string& what) const {
    const std::string msg = gdal::last_error_message();
    throw FormatError(std::string(kWho) + ": " + out.final_path().string() + ": " + what +
                      (msg.empty() ? "" : ": " + msg));
  }
  void field(const char* name, OGRFieldType type, OGRFieldSubType sub = OFSTNone) {
    OGRFieldDefn f(name, type);
    f.SetSubType(sub);
    if (layer->CreateField(&f) != OGRERR_NONE) fail(std::string("cannot create field ") + name);
  }
  void add(OGRFeature& f) {
    if (layer->CreateFeature(&f) != OGRERR_NONE) fail("cannot write a feature");
  }
  void close() {
    gdal::close_checked(std::move(ds), out.final_path().string(), kWho);
    out.commit();
  }
};

void set_real(OGRFeature& f, const char* name, double v) {
  if (std::isfinite(v)) {
    f.SetField(name, v);
  } else {
    f.SetFieldNull(f.GetFieldIndex(name));
  }
}

}  // namespace

/// What one line collects: its track, the seabed edges of each side, ping count and times.
struct GeoTruthWriter::LineData {
  std::vector<Eigen::Vector2d> track_xy;
  std::uint64_t pings = 0;
  UtcTime first_time{}, last_time{};
  /// Per side: the union of the strips between consecutive pings' seabed edges.
  std::unique_ptr<OGRGeometry> coverage[2];
  std::uint64_t coverage_pings[2] = {0, 0};
  std::optional<Edge> previous[2];
  std::unique_ptr<OGRMultiPolygon> pieces[2];

  void add_edge(int side, const std::optional<Edge>& e) {
    if (e) ++coverage_pings[side];
    if (e && previous[side]) {
      const Edge& a = *previous[side];
      const Edge& b = *e;
      // The strip between the two pings as two triangles: a quadrilateral whose far edges cross
      // (the inner side of a turn) is not a valid polygon, two triangles always are.
      const Eigen::Vector2d tri[2][3] = {{a.near_xy, a.far_xy, b.far_xy},
                                         {a.near_xy, b.far_xy, b.near_xy}};
      for (const auto& t : tri) {
        const double area = 0.5 * std::abs((t[1] - t[0]).x() * (t[2] - t[0]).y() -
                                           (t[1] - t[0]).y() * (t[2] - t[0]).x());
        if (!(area > 1e-9)) continue;
        auto ring = std::make_unique<OGRLinearRing>();
        for (const auto& p : t) ring->addPoint(p.x(), p.y());
        ring->addPoint(t[0].x(), t[0].y());
        auto poly = std::make_unique<OGRPolygon>();
        poly->addRingDirectly(ring.release());
        if (!pieces[side]) pieces[side] = std::make_unique<OGRMultiPolygon>();
        pieces[side]->addGeometryDirectly(poly.release());
      }
    }
    previous[side] = e;
  }

  /// The union of the pieces so far (local frame).
  void merge(int side) {
    if (!pieces[side] || pieces[side]->IsEmpty()) return;
    std::unique_ptr<OGRGeometry> u(pieces[side]->UnionCascaded());
    if (!u) u.reset(pieces[side]->clone());  // without GEOS: the triangles themselves
    pieces[side].reset();
    if (coverage[side]) {
      std::unique_ptr<OGRGeometry> both(coverage[side]->Union(u.get()));
      if (both) u = std::move(both);
    }
    coverage[side] = std::move(u);
  }
};

GeoTruthWriter::GeoTruthWriter(std::filesystem::path dir, std::shared_ptr<const Scene> scene,
                               std::vector<std::string> line_names, bool overwrite)
    : dir_(std::move(dir)),
      scene_(std::move(scene)),
      names_(std::move(line_names)),
      overwrite_(overwrite) {
  if (!scene_) throw InputError("truth vectors: scene = null. Violated constraint: a scene");
  const Eigen::Vector4d bb = scene_->bathymetry.bounds();
  centre_xy_m_ = {0.5 * (bb[0] + bb[2]), 0.5 * (bb[1] + bb[3])};
  for (const ObjectPrimitive& o : scene_->objects.primitives()) ids_.push_back(o.id);
  for (const ObjectRecord& r : scene_->object_records) ids_.push_back(r.id);
  std::sort(ids_.begin(), ids_.end());
  ids_.erase(std::unique(ids_.begin(), ids_.end()), ids_.end());
  seen_.assign(ids_.size(), std::vector<Seen>(names_.size()));
  marked_.assign(ids_.size(), 0);
  for (std::size_t l = 0; l < names_.size(); ++l) lines_.push_back(std::make_unique<LineData>());
}

GeoTruthWriter::~GeoTruthWriter() = default;

void GeoTruthWriter::begin_line(std::size_t line) {
  if (line >= lines_.size()) {
    for (std::size_t l = lines_.size(); l <= line; ++l) {
      lines_.push_back(std::make_unique<LineData>());
      names_.push_back("line" + std::to_string(l + 1));
    }
    for (auto& s : seen_) s.resize(lines_.size());
  }
}

void GeoTruthWriter::ping(const RenderedPing& p) {
  const std::size_t line = p.pose.line;
  if (line >= lines_.size()) begin_line(line);
  LineData& d = *lines_[line];
  if (d.pings == 0) d.first_time = p.pose.time_utc;
  d.last_time = p.pose.time_utc;
  ++d.pings;
  d.track_xy.push_back(p.pose.sensor_xy_m);
  if (p.port.truth_class.empty() && p.starboard.truth_class.empty()) return;
  // The objects whose id some sample carries, once per ping.
  std::size_t marked_count = 0;
  for (const SideOutput* s : {&p.port, &p.starboard}) {
    for (const std::int32_t id : s->truth_label) {
      if (id <= 0) continue;
      const auto it = std::lower_bound(ids_.begin(), ids_.end(), id);
      if (it == ids_.end() || *it != id) continue;
      const auto k = static_cast<std::size_t>(it - ids_.begin());
      if (marked_[k]) continue;
      marked_[k] = 1;
      ++marked_count;
      Seen& sn = seen_[k][line];
      if (sn.pings == 0) {
        sn.first = p.pose.ping_in_line;
        sn.first_time = p.pose.time_utc;
      }
      sn.last = p.pose.ping_in_line;
      sn.last_time = p.pose.time_utc;
      ++sn.pings;
    }
  }
  if (marked_count > 0) std::fill(marked_.begin(), marked_.end(), std::uint8_t{0});
  d.add_edge(0, seabed_edge(p.port));
  d.add_edge(1, seabed_edge(p.starboard));
  // Merge in batches, so that the pieces held stay few.
  for (int side = 0; side < 2; ++side) {
    if (d.pieces[side] && d.pieces[side]->getNumGeometries() >= 4096) d.merge(side);
  }
}

void GeoTruthWriter::end_line(std::size_t line) {
  if (line >= lines_.size()) return;
  for (int side = 0; side < 2; ++side) lines_[line]->merge(side);
}

std::vector<Sighting> GeoTruthWriter::sightings(std::int32_t id) const {
  std::vector<Sighting> out;
  const auto it = std::lower_bound(ids_.begin(), ids_.end(), id);
  if (it == ids_.end() || *it != id) return out;
  const auto& lines = seen_[static_cast<std::size_t>(it - ids_.begin())];
  for (std::size_t l = 0; l < lines.size(); ++l) {
    const Seen& s = lines[l];
    if (s.pings > 0) out.push_back({l, s.first, s.last, s.pings, s.first_time, s.last_time});
  }
  return out;
}

namespace {

/// Extents of the primitives of one object along its heading, across it and vertically, metres;
/// the diameter of a cylinder or a sphere (NaN otherwise).
struct Extents {
  double length = kNaN, width = kNaN, height = kNaN, diameter = kNaN;
};

Extents object_extents(const std::vector<const ObjectPrimitive*>& parts, double heading_rad) {
  Extents e;
  if (parts.empty()) return e;
  if (parts.size() == 1) {
    const ObjectPrimitive& p = *parts[0];
    e.length = 2.0 * p.half_extent_m.x();
    e.width = 2.0 * p.half_extent_m.y();
    e.height = 2.0 * p.half_extent_m.z();
    const bool round_section =
        p.shape == ObjectShape::kCylinder ||
        (p.shape == ObjectShape::kEllipsoid && p.half_extent_m.x() == p.half_extent_m.y() &&
         p.half_extent_m.y() == p.half_extent_m.z());
    if (round_section) e.diameter = 2.0 * p.half_extent_m.y();
    return e;
  }
  // Several parts (a wreck): the corners of their footprints along and across the heading, and
  // from the lowest base to the highest top.
  const Eigen::Vector2d fwd(std::sin(heading_rad), std::cos(heading_rad));
  const Eigen::Vector2d across(fwd.y(), -fwd.x());
  double a0 = INFINITY, a1 = -INFINITY, c0 = INFINITY, c1 = -INFINITY, z0 = INFINITY,
         z1 = -INFINITY;
  for (const ObjectPrimitive* p : parts) {
    const Eigen::Vector2d u = p->axis_u();
    const Eigen::Vector2d v(u.y(), -u.x());
    for (const double su : {-1.0, 1.0}) {
      for (const double sv : {-1.0, 1.0}) {
        const Eigen::Vector2d c =
            p->centre_xy_m + su * p->half_extent_m.x() * u + sv * p->half_extent_m.y() * v;
        a0 = std::min(a0, c.dot(fwd));
        a1 = std::max(a1, c.dot(fwd));
        c0 = std::min(c0, c.dot(across));
        c1 = std::max(c1, c.dot(across));
      }
    }
    for (const float b : p->base_z_m) {
      z0 = std::min(z0, static_cast<double>(b));
      z1 = std::max(z1, static_cast<double>(b) + 2.0 * p->half_extent_m.z());
    }
  }
  e.length = a1 - a0;
  e.width = c1 - c0;
  if (z1 > z0) e.height = z1 - z0;
  return e;
}

/// Local frame -> longitude, latitude (degrees at I/O only), in place.
void to_geographic(OGRGeometry& g, const GeoFrame& frame) {
  struct Visitor : public OGRDefaultGeometryVisitor {
    const GeoFrame& frame;
    explicit Visitor(const GeoFrame& f) : frame(f) {}
    using OGRDefaultGeometryVisitor::visit;
    void visit(OGRPoint* p) override {
      const Geodetic q = frame.geodetic_from_local({p->getX(), p->getY()});
      p->setX(deg_from_rad(q.lon_rad));
      p->setY(deg_from_rad(q.lat_rad));
    }
  } v(frame);
  g.accept(&v);
}

/// The fields of targets.geojson.
void add_target_fields(VectorFile& targets) {
  targets.field("id", OFTInteger);
  for (const char* f : {"name", "type", "shape", "material"}) targets.field(f, OFTString);
  for (const char* f :
       {"lat_deg", "lon_deg", "east_m", "north_m", "utm_easting_m", "utm_northing_m"}) {
    targets.field(f, OFTReal);
  }
  targets.field("epsg", OFTInteger);
  for (const char* f :
       {"length_m", "width_m", "height_m", "diameter_m", "heading_deg", "clearance_m", "embed"}) {
    targets.field(f, OFTReal);
  }
  targets.field("pings", OFTInteger64);
  targets.field("seen_by", OFTString, OFSTJSON);
}

/// The fields of object `id` of `scene` but its sightings: from its record, or for a scene built
/// in code from its first primitive. Returns its position.
Geodetic set_target_fields(OGRFeature& f, const Scene& scene, std::int32_t id,
                           const Eigen::Vector2d& centre_xy_m) {
  const GeoFrame& frame = scene.frame;
  std::vector<const ObjectPrimitive*> parts;
  for (const ObjectPrimitive& o : scene.objects.primitives()) {
    if (o.id == id) parts.push_back(&o);
  }
  const ObjectRecord* rec = nullptr;
  for (const ObjectRecord& r : scene.object_records) {
    if (r.id == id) rec = &r;
  }
  ObjectRecord r;
  if (rec) {
    r = *rec;
  } else if (!parts.empty()) {  // a scene built in code: the primitive's own numbers
    r.id = id;
    r.type = to_string(parts[0]->shape);
    r.position_xy_m = parts[0]->centre_xy_m;
    r.heading_rad = parts[0]->heading_rad;
    r.clearance_m = parts[0]->clearance_m;
  }
  f.SetField("id", id);
  f.SetField("name", r.name.empty() ? (r.type + "-" + std::to_string(id)).c_str() : r.name.c_str());
  f.SetField("type", r.type.c_str());
  f.SetField("shape", parts.empty() ? "" : to_string(parts[0]->shape));
  f.SetField("material", r.material.c_str());
  const Geodetic g = frame.geodetic_from_local(r.position_xy_m);
  f.SetField("lat_deg", deg_from_rad(g.lat_rad));
  f.SetField("lon_deg", deg_from_rad(g.lon_rad));
  f.SetField("east_m", r.position_xy_m.x() - centre_xy_m.x());
  f.SetField("north_m", r.position_xy_m.y() - centre_xy_m.y());
  const Eigen::Vector2d en = frame.projected_from_local(r.position_xy_m);
  f.SetField("utm_easting_m", en.x());
  f.SetField("utm_northing_m", en.y());
  f.SetField("epsg", frame.epsg());
  const Extents e = object_extents(parts, r.heading_rad);
  set_real(f, "length_m", e.length);
  set_real(f, "width_m", e.width);
  set_real(f, "height_m", e.height);
  set_real(f, "diameter_m", e.diameter);
  f.SetField("heading_deg", deg_from_rad(r.heading_rad));
  f.SetField("clearance_m", r.clearance_m);
  f.SetField("embed", r.embed_fraction);
  return g;
}

}  // namespace

void GeoTruthWriter::finish() {
  gdal::ensure_registered();
  const GeoFrame& frame = scene_->frame;

  // Targets.
  VectorFile targets(dir_ / "targets.geojson", overwrite_, "targets", wkbPoint);
  add_target_fields(targets);
  for (std::size_t k = 0; k < ids_.size(); ++k) {
    const std::int32_t id = ids_[k];
    OGRFeature f(targets.layer->GetLayerDefn());
    const Geodetic g = set_target_fields(f, *scene_, id, centre_xy_m_);
    std::ostringstream json;
    json << "[";
    std::uint64_t total = 0;
    bool first = true;
    for (const Sighting& s : sightings(id)) {
      json << (first ? "" : ", ") << "{\"line\": \"" << names_[s.line]
           << "\", \"first_ping\": " << s.first_ping << ", \"last_ping\": " << s.last_ping
           << ", \"pings\": " << s.pings << ", \"first_time\": \""
           << calendar::utc_text(s.first_time) << "\", \"last_time\": \""
           << calendar::utc_text(s.last_time) << "\"}";
      total += s.pings;
      first = false;
    }
    json << "]";
    f.SetField("pings", static_cast<GIntBig>(total));
    f.SetField("seen_by", json.str().c_str());
    OGRPoint pt(deg_from_rad(g.lon_rad), deg_from_rad(g.lat_rad));
    f.SetGeometry(&pt);
    targets.add(f);
  }

  // Tracks and coverage.
  VectorFile tracks(dir_ / "tracks.geojson", overwrite_, "tracks", wkbLineString);
  tracks.field("line", OFTString);
  tracks.field("pings", OFTInteger64);
  tracks.field("first_ping_time", OFTString);
  tracks.field("last_ping_time", OFTString);
  VectorFile coverage(dir_ / "coverage.geojson", overwrite_, "coverage", wkbMultiPolygon);
  coverage.field("line", OFTString);
  coverage.field("side", OFTString);
  coverage.field("pings", OFTInteger64);
  for (std::size_t l = 0; l < lines_.size(); ++l) {
    LineData& d = *lines_[l];
    if (d.pings == 0) continue;
    OGRFeature t(tracks.layer->GetLayerDefn());
    t.SetField("line", names_[l].c_str());
    t.SetField("pings", static_cast<GIntBig>(d.pings));
    t.SetField("first_ping_time", calendar::utc_text(d.first_time).c_str());
    t.SetField("last_ping_time", calendar::utc_text(d.last_time).c_str());
    OGRLineString ls;
    for (const Eigen::Vector2d& xy : d.track_xy) {
      const Geodetic q = frame.geodetic_from_local(xy);
      ls.addPoint(deg_from_rad(q.lon_rad), deg_from_rad(q.lat_rad));
    }
    if (d.track_xy.size() == 1) ls.addPoint(ls.getX(0), ls.getY(0));
    t.SetGeometry(&ls);
    tracks.add(t);
    for (int side = 0; side < 2; ++side) {
      d.merge(side);
      if (!d.coverage[side]) continue;
      std::unique_ptr<OGRGeometry> g(
          OGRGeometryFactory::forceToMultiPolygon(d.coverage[side]->clone()));
      to_geographic(*g, frame);
      OGRFeature c(coverage.layer->GetLayerDefn());
      c.SetField("line", names_[l].c_str());
      c.SetField("side", side == 0 ? "port" : "starboard");
      c.SetField("pings", static_cast<GIntBig>(d.coverage_pings[side]));
      c.SetGeometryDirectly(g.release());
      coverage.add(c);
    }
  }
  targets.close();
  tracks.close();
  coverage.close();
  files_ = {dir_ / "targets.geojson", dir_ / "tracks.geojson", dir_ / "coverage.geojson"};
}

void GeoTruthWriter::abort() noexcept {
  lines_.clear();
}

}  // namespace sonarsynth::geo_truth
