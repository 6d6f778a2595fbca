// SPDX-License-Identifier: MIT
// The scene's local frame (docs/python.md, "The local frame"): GeoFrame's conversions over numpy
// arrays, and the offset of the scene file's positions.
#include <cmath>
#include <limits>
#include <string>

#include "bindings.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::python {

namespace {

/// The local frame of a Simulation's scene and the centre of its bathymetry grid (the origin of a
/// scene file's east_m / north_m), copied out of the scene.
struct SceneFrame {
  GeoFrame frame;
  Eigen::Vector2d grid_centre_xy_m;
};

SceneFrame frame_of(const PySimulation& s) {
  return {s.scene->frame, s.scene->bathymetry.centre_xy_m()};
}

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// f(a[i], b[i]) -> (u[i], v[i]) over a and b broadcast against each other (numpy's rules);
// Python floats for scalars, arrays of the broadcast shape otherwise.
template <class F>
py::tuple map2(const py::object& a_in, const py::object& b_in, F f) {
  const py::tuple ab = py::module_::import("numpy").attr("broadcast_arrays")(a_in, b_in);
  const Array a = Array::ensure(ab[0]), b = Array::ensure(ab[1]);
  if (!a || !b) throw py::error_already_set();
  std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim());
  Array u(shape), v(shape);
  const double* pa = a.data();
  const double* pb = b.data();
  double* pu = u.mutable_data();
  double* pv = v.mutable_data();
  for (py::ssize_t i = 0; i < a.size(); ++i) {
    const Eigen::Vector2d r = f(pa[i], pb[i], i);
    pu[i] = r.x();
    pv[i] = r.y();
  }
  if (a.ndim() == 0) return py::make_tuple(pu[0], pv[0]);
  return py::make_tuple(u, v);
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

py::tuple local_from_geodetic(const SceneFrame& f, const py::object& lat_deg,
                              const py::object& lon_deg) {
  return map2(lat_deg, lon_deg, [&](double lat, double lon, py::ssize_t i) -> Eigen::Vector2d {
    if (std::isnan(lat) || std::isnan(lon)) return {kNaN, kNaN};
    if (!(std::abs(lat) <= 90.0) || !std::isfinite(lon)) {
      throw InputError("local_from_geodetic: element " + std::to_string(i) +
                       ": lat_deg = " + std::to_string(lat) + ", lon_deg = " + std::to_string(lon) +
                       ". Violated constraint: -90 <= lat_deg <= 90, lon_deg finite (NaN gives "
                       "NaN)");
    }
    return f.frame.local_from_geodetic({rad_from_deg(lat), rad_from_deg(lon), 0.0});
  });
}

py::tuple geodetic_from_local(const SceneFrame& f, const py::object& x_m, const py::object& y_m) {
  return map2(x_m, y_m, [&](double x, double y, py::ssize_t i) -> Eigen::Vector2d {
    if (std::isnan(x) || std::isnan(y)) return {kNaN, kNaN};
    if (!std::isfinite(x) || !std::isfinite(y)) {
      throw InputError("geodetic_from_local: element " + std::to_string(i) +
                       ": x_m = " + std::to_string(x) + ", y_m = " + std::to_string(y) +
                       ". Violated constraint: finite (NaN gives NaN)");
    }
    const Geodetic g = f.frame.geodetic_from_local({x, y});
    return {deg_from_rad(g.lat_rad), deg_from_rad(g.lon_rad)};
  });
}

}  // namespace

void bind_frame(py::module_& m, py::class_<PySimulation>& cls) {
  py::class_<SceneFrame>(
      m, "SceneFrame",
      "The local frame of a scene (docs/python.md, \"The local frame\"): a UTM/UPS zone "
      "(WGS 84) shifted by an origin, x_m = easting - origin_easting_m (grid east), y_m = "
      "northing - origin_northing_m (grid north), z up on the bathymetry's datum; metres. "
      "Every position of the module (poses, add_line, add_object, bounds_m) is in it. A scene "
      "file's positions (east_m, north_m) are metres from the bathymetry grid's centre: "
      "local = grid_centre_m + (east_m, north_m) (local_from_scene). Conversions take numpy "
      "arrays or scalars (broadcast) and give the same shape; NaN gives NaN.")
      .def_property_readonly(
          "epsg", [](const SceneFrame& f) { return f.frame.epsg(); },
          "EPSG code of the WGS 84 UTM/UPS zone (326zz north, 327zz south, 32661 / 32761 UPS).")
      .def_property_readonly(
          "zone", [](const SceneFrame& f) { return f.frame.zone(); }, "UTM zone 1..60, 0 = UPS.")
      .def_property_readonly(
          "northp", [](const SceneFrame& f) { return f.frame.northp(); },
          "True for the northern hemisphere (UPS: the north pole).")
      .def_property_readonly(
          "origin_easting_m", [](const SceneFrame& f) { return f.frame.origin_easting_m(); },
          "Easting of the local origin (x_m = 0) in the zone, metres.")
      .def_property_readonly(
          "origin_northing_m", [](const SceneFrame& f) { return f.frame.origin_northing_m(); },
          "Northing of the local origin (y_m = 0) in the zone, metres (with the false northing "
          "of 10,000 km in the southern hemisphere).")
      .def_property_readonly(
          "origin_lat_deg",
          [](const SceneFrame& f) {
            return deg_from_rad(f.frame.geodetic_from_local({0, 0}).lat_rad);
          },
          "WGS 84 latitude of the local origin, degrees.")
      .def_property_readonly(
          "origin_lon_deg",
          [](const SceneFrame& f) {
            return deg_from_rad(f.frame.geodetic_from_local({0, 0}).lon_rad);
          },
          "WGS 84 longitude of the local origin, degrees.")
      .def_property_readonly(
          "grid_centre_m",
          [](const SceneFrame& f) {
            return py::make_tuple(f.grid_centre_xy_m.x(), f.grid_centre_xy_m.y());
          },
          "(x_m, y_m) of the bathymetry grid's centre (the centre of its node area): the origin "
          "of a scene file's east_m / north_m.")
      .def("local_from_geodetic", &local_from_geodetic, py::arg("lat_deg"), py::arg("lon_deg"),
           "(x_m, y_m) in the local frame of WGS 84 positions in degrees; ValueError for a "
           "latitude outside [-90, 90], an infinite longitude, or a point that cannot be "
           "projected into the zone.")
      .def("geodetic_from_local", &geodetic_from_local, py::arg("x_m"), py::arg("y_m"),
           "(lat_deg, lon_deg), WGS 84 degrees, of local positions in metres.")
      .def(
          "local_from_scene",
          [](const SceneFrame& f, const py::object& east_m, const py::object& north_m) {
            return map2(east_m, north_m, [&](double e, double n, py::ssize_t) {
              return Eigen::Vector2d(f.grid_centre_xy_m + Eigen::Vector2d(e, n));
            });
          },
          py::arg("east_m"), py::arg("north_m"),
          "(x_m, y_m) in the local frame of a scene file's position {east_m, north_m} (metres "
          "from the grid's centre along the grid axes): grid_centre_m + (east_m, north_m).")
      .def(
          "scene_from_local",
          [](const SceneFrame& f, const py::object& x_m, const py::object& y_m) {
            return map2(x_m, y_m, [&](double x, double y, py::ssize_t) {
              return Eigen::Vector2d(Eigen::Vector2d(x, y) - f.grid_centre_xy_m);
            });
          },
          py::arg("x_m"), py::arg("y_m"),
          "(east_m, north_m) as a scene file writes them of local positions: (x_m, y_m) - "
          "grid_centre_m.")
      .def("__repr__", [](const SceneFrame& f) {
        return "SceneFrame(epsg=" + std::to_string(f.frame.epsg()) +
               ", origin_easting_m=" + std::to_string(f.frame.origin_easting_m()) +
               ", origin_northing_m=" + std::to_string(f.frame.origin_northing_m()) +
               ", grid_centre_m=(" + std::to_string(f.grid_centre_xy_m.x()) + ", " +
               std::to_string(f.grid_centre_xy_m.y()) + "))";
      });

  cls.def_property_readonly(
      "scene_frame", &frame_of,
      "The scene's local frame (SceneFrame): its zone, origin and the "
      "offset of the scene file's positions; conversions to and from WGS 84.");
  cls.def(
      "local_from_geodetic",
      [](const PySimulation& s, const py::object& lat_deg, const py::object& lon_deg) {
        return local_from_geodetic(frame_of(s), lat_deg, lon_deg);
      },
      py::arg("lat_deg"), py::arg("lon_deg"),
      "Local (x_m, y_m) in metres of WGS 84 positions in degrees: "
      "scene_frame.local_from_geodetic.");
}

}  // namespace sonarsynth::python
