// SPDX-License-Identifier: MIT
// The `survey` section of a simulation file (docs/scene-format.md): the vehicle, its
// disturbance and the survey lines, given as waypoints or read from a vector file.
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>
#include <set>
#include <sstream>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/option_table.hpp"
#include "sonarsynth/formats/config/simulation_file_parts.hpp"
#include "sonarsynth/formats/raster/gdal_util.hpp"

namespace sonarsynth {
namespace simulation_file {
namespace {

namespace fs = std::filesystem;

Eigen::Vector2d position(const Scene& scene, const Eigen::Vector2d& centre, const Fields& p) {
  p.only({"lat_deg", "lon_deg", "east_m", "north_m"});
  const bool geographic = p.node()["lat_deg"].IsDefined() || p.node()["lon_deg"].IsDefined();
  if (geographic) {
    // Both are required (a null or missing one is not taken as 0).
    const double lat = p.number("lat_deg"), lon = p.number("lon_deg");
    if (!(lat >= -90.0 && lat <= 90.0)) p.fail_value("lat_deg", "-90 <= lat_deg <= 90");
    if (!(lon >= -180.0 && lon <= 360.0)) p.fail_value("lon_deg", "-180 <= lon_deg <= 360");
    try {
      return scene.frame.local_from_geodetic({rad_from_deg(lat), rad_from_deg(lon), 0.0});
    } catch (const InputError& e) {
      p.fail("", e.what());
    }
  }
  const Eigen::Vector2d xy = centre + Eigen::Vector2d(p.number("east_m"), p.number("north_m"));
  for (const char* key : {"east_m", "north_m"}) {
    if (!(std::abs(p.number(key)) <= kMaxWaypointOffsetM)) {
      p.fail_value(key, std::string("|") + key + "| <= 1e6 (metres from the grid centre)");
    }
  }
  return xy;
}

}  // namespace

void read_survey_section(const Fields& sv, const std::string& path, const fs::path& base_dir,
                         SimulationSetup& setup) {
  Scene& scene = setup.scene;
  const Eigen::Vector2d centre = scene.bathymetry.centre_xy_m();
  sv.only(keys_of("survey", {"start_time", "lever_arm_m", "disturbance", "lines"}));
  if (sv.given("start_time")) {
    setup.start_time = parse_utc(sv.text("start_time"), path + ": survey.start_time");
  }
  VehicleConfig& v = setup.vehicle;
  if (sv.has("altitude_m") && sv.has("depth_m"))
    sv.fail("", "give altitude_m or depth_m, not both");
  options::read_all(sv, "survey", setup);
  if (v.depth_mode == VehicleConfig::DepthMode::kDepth) {
    const auto [lo, hi] = scene.bathymetry.height_range();
    setup.reference_altitude_m = std::max(0.5, -v.depth_m - 0.5 * (lo + hi));
  } else {
    setup.reference_altitude_m = v.altitude_m;
  }
  if (sv.has("lever_arm_m")) {
    const auto la = sv.numbers("lever_arm_m", 3);
    v.lever_arm_m = {la[0], la[1], la[2]};
  }
  if (sv.has("disturbance")) {
    const Fields d = sv.child("disturbance");
    d.only(keys_of("survey.disturbance"));
    options::read_all(d, "survey.disturbance", setup);
  }
  wrap(sv, [&] { v.validate(); });
  for (const Fields& l : sv.sequence("lines")) {
    if (l.has("file")) {
      l.only({"file", "layer"});
      const std::string vpath = yaml::resolve_path(base_dir, l.text("file"));
      gdal::VectorLayer vl =
          gdal::open_vector_layer(vpath, l.text("layer", ""), scene.frame.epsg(), false, "survey");
      OGRLayer* layer = vl.layer;
      for (auto& feature : *layer) {
        OGRGeometry* g = feature->GetGeometryRef();
        if (!g || wkbFlatten(g->getGeometryType()) != wkbLineString) continue;
        std::unique_ptr<OGRGeometry> gc(g->clone());
        if (gc->transform(vl.to_target.get()) != OGRERR_NONE)
          throw FormatError(vpath + ": cannot transform a line");
        SurveyLine line;
        const int name_idx = feature->GetFieldIndex("name");
        line.name = name_idx >= 0 ? feature->GetFieldAsString(name_idx)
                                  : "line" + std::to_string(setup.lines.size() + 1);
        for (const OGRPoint& pt : *gc->toLineString()) {
          const Eigen::Vector2d xy = scene.frame.local_from_projected({pt.getX(), pt.getY()});
          if (!((xy - centre).cwiseAbs().maxCoeff() <= kMaxWaypointOffsetM)) {
            std::ostringstream os;
            os.precision(10);
            os << vpath << ": line '" << line.name << "' vertex (" << pt.getX() << ", " << pt.getY()
               << ") in EPSG:" << scene.frame.epsg() << " is "
               << (xy - centre).cwiseAbs().maxCoeff()
               << " m from the bathymetry grid's centre. Violated constraint: <= 1e6 m";
            throw InputError(os.str());
          }
          line.waypoints_xy_m.push_back(xy);
        }
        setup.lines.push_back(std::move(line));
      }
      continue;
    }
    l.only({"name", "waypoints"});
    SurveyLine line;
    line.name = l.text("name", "line" + std::to_string(setup.lines.size() + 1));
    for (const Fields& w : l.sequence("waypoints"))
      line.waypoints_xy_m.push_back(position(scene, centre, w));
    if (line.waypoints_xy_m.size() < 2) l.fail("waypoints", "a line needs at least 2 waypoints");
    setup.lines.push_back(std::move(line));
  }
  if (setup.lines.empty()) sv.fail("lines", "no survey lines");
  // Line names become file names: unique, and made of letters, digits, '-', '_' and '.'.
  std::set<std::string> names;
  for (const SurveyLine& line : setup.lines) {
    const bool safe = !line.name.empty() && line.name[0] != '.' &&
                      std::all_of(line.name.begin(), line.name.end(), [](char ch) {
                        return std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' ||
                               ch == '_' || ch == '.';
                      });
    if (!safe)
      sv.fail("lines",
              "line name '" + line.name + "' must use only letters, digits, '-', '_', '.'");
    if (!names.insert(line.name).second)
      sv.fail("lines", "line name '" + line.name + "' is used twice");
  }
}

}  // namespace simulation_file

using simulation_file::kMaxWaypointOffsetM;

void check_survey_line(const Scene& scene, const SurveyLine& line, const std::string& name) {
  const Eigen::Vector2d centre = scene.bathymetry.centre_xy_m();
  for (std::size_t k = 0; k < line.waypoints_xy_m.size(); ++k) {
    const Eigen::Vector2d& w = line.waypoints_xy_m[k];
    const double offset_m = (w - centre).cwiseAbs().maxCoeff();
    if (w.allFinite() && offset_m <= kMaxWaypointOffsetM) continue;
    std::ostringstream os;
    os.precision(10);
    os << name << ": survey line '" << line.name << "' waypoint " << k << " = (" << w.x() << ", "
       << w.y() << ") m";
    if (w.allFinite()) {
      os << " is " << offset_m
         << " m from the bathymetry grid's centre. Violated constraint: <= " << kMaxWaypointOffsetM
         << " m";
    } else {
      os << ". Violated constraint: finite x and y";
    }
    os << " (waypoints counted from 0)";
    throw InputError(os.str());
  }
}

}  // namespace sonarsynth
