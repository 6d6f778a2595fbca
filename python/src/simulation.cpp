// SPDX-License-Identifier: MIT
// Simulation: construction (scene file, YAML text, numpy heights), the scene builder (objects,
// survey lines), poses and the derived calibration.
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <optional>

#include "bindings.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/scene_file.hpp"
#include "sonarsynth/formats/config/scene_objects.hpp"
#include "sonarsynth/object_types.hpp"
#include "sonarsynth/scene_object.hpp"
#include "sonarsynth/triangle_mesh.hpp"

namespace sonarsynth::python {

namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

SimulationOverrides overrides_of(std::optional<std::uint64_t> seed, std::optional<double> range_m,
                                 std::optional<std::size_t> samples,
                                 std::optional<std::string> quality) {
  SimulationOverrides o;
  o.seed = seed;
  o.range_m = range_m;
  o.samples = samples;
  o.quality = std::move(quality);
  return o;
}

// One element of `a` (length 1 = broadcast).
double at(const py::array_t<double, py::array::forcecast>& a, py::ssize_t i) {
  return a.size() == 1 ? a.data()[0] : a.data()[i];
}

}  // namespace

PoseRecord record_of(const PingPose& p) {
  return PoseRecord{p.line,
                    p.ping_in_line,
                    p.ping_index.value_or(0),
                    p.time_utc.time_since_epoch().count(),
                    p.sensor_xy_m.x(),
                    p.sensor_xy_m.y(),
                    p.sensor_z_m,
                    p.reference_xy_m.x(),
                    p.reference_xy_m.y(),
                    p.heading_rad,
                    p.pitch_rad,
                    p.roll_rad,
                    p.heave_m,
                    p.altitude_m,
                    p.speed_m_s,
                    p.along_track_m};
}

PingPose pose_of(const PoseRecord& r) {
  PingPose p;
  p.line = r.line;
  p.ping_in_line = r.ping_in_line;
  p.ping_index = r.ping_index;
  p.time_utc = UtcTime(std::chrono::microseconds(r.time_utc_us));
  p.sensor_xy_m = {r.sensor_x_m, r.sensor_y_m};
  p.sensor_z_m = r.sensor_z_m;
  p.reference_xy_m = {r.reference_x_m, r.reference_y_m};
  p.heading_rad = r.heading_rad;
  p.pitch_rad = r.pitch_rad;
  p.roll_rad = r.roll_rad;
  p.heave_m = r.heave_m;
  p.altitude_m = r.altitude_m;
  p.speed_m_s = r.speed_m_s;
  p.along_track_m = r.along_track_m;
  return p;
}

PySimulation::PySimulation(SimulationSetup s, std::string n)
    : name(std::move(n)),
      setup(std::move(s)),
      scene(std::make_shared<Scene>(std::move(setup.scene))) {}

Scene& PySimulation::mutable_scene() {
  sim_.reset();
  if (scene.use_count() > 1) scene = std::make_shared<Scene>(*scene);
  return *scene;
}

Survey PySimulation::survey() const {
  if (setup.lines.empty()) throw InputError(name + ": survey.lines: none (add_line)");
  return setup.make_survey();
}

std::shared_ptr<const Simulator> PySimulation::simulator() {
  if (sim_) return sim_;
  setup.config.validate();
  setup.vehicle.validate();
  check_cross_keys(setup, name);  // what a scene file with these values would refuse
  // The reference altitude of the global calibration, as a scene file derives it.
  double reference_altitude_m = setup.vehicle.altitude_m;
  if (setup.vehicle.depth_mode == VehicleConfig::DepthMode::kDepth) {
    const auto [lo, hi] = scene->bathymetry.height_range();
    reference_altitude_m = std::max(0.5, -setup.vehicle.depth_m - 0.5 * (lo + hi));
  }
  std::vector<PingPose> pilot;
  std::optional<Survey> sv;
  if (!setup.lines.empty()) sv.emplace(setup.make_survey());
  const std::shared_ptr<const Scene> sc = scene;
  {
    py::gil_scoped_release release;
    if (sv) pilot = pilot_poses(*sv, sc->bathymetry);  // as run_simulation
    sim_ = std::make_shared<const Simulator>(sc, setup.config, reference_altitude_m, pilot);
  }
  return sim_;
}

namespace {

// Simulation.from_file, from_yaml and from_heights.
void bind_constructors(py::class_<PySimulation>& cls) {
  cls.def_static(
      "from_file",
      [](const std::filesystem::path& path, std::optional<std::uint64_t> seed,
         std::optional<double> range_m, std::optional<std::size_t> samples,
         std::optional<std::string> quality) {
        const SimulationOverrides o = overrides_of(seed, range_m, samples, quality);
        std::optional<SimulationSetup> s;
        {
          py::gil_scoped_release release;
          s.emplace(load_simulation(path.string(), o));
        }
        return PySimulation(std::move(*s), path.string());
      },
      py::arg("path"), py::kw_only(), py::arg("seed") = py::none(), py::arg("range_m") = py::none(),
      py::arg("samples") = py::none(), py::arg("quality") = py::none(),
      "Loads a scene file (YAML, docs/scene-format.md) with its survey, sonar, render, noise "
      "and output sections, as `sonarsynth simulate` does; seed, range_m (metres), samples "
      "(per side) and quality ('fast', 'default', 'high') override the file like --seed, "
      "--range, --samples, --quality. Raises ValueError / FormatError naming file, key and "
      "value.");
  cls.def_static(
      "from_yaml",
      [](const std::string& text, const std::string& name, const std::filesystem::path& base_dir,
         std::optional<std::uint64_t> seed) {
        SimulationOverrides o;
        o.seed = seed;
        std::optional<SimulationSetup> s;
        {
          py::gil_scoped_release release;
          s.emplace(load_simulation_from_string(text, name, base_dir, o));
        }
        return PySimulation(std::move(*s), name);
      },
      py::arg("text"), py::arg("name") = "<string>", py::arg("base_dir") = ".", py::kw_only(),
      py::arg("seed") = py::none(),
      "As from_file, from scene-file text: `name` stands for the file in messages, relative "
      "paths are relative to `base_dir`.");
  cls.def_static(
      "from_heights",
      [](py::array_t<float, py::array::c_style | py::array::forcecast> heights_m, double x0_m,
         double y0_m, double dx_m, double dy_m, double lat_deg, double lon_deg,
         const std::string& name) {
        // The checks of a scene file's grid (formats/raster/gdal_grid.cpp) and of its seabed
        // (formats/config/scene_bathymetry.cpp), with the arguments' names.
        const std::string what = name + ": from_heights";
        if (heights_m.ndim() != 2) {
          throw InputError(what + ": heights_m has " + std::to_string(heights_m.ndim()) +
                           " dimensions. Violated constraint: a 2-D array (rows, cols)");
        }
        GridGeometry g{x0_m,
                       y0_m,
                       dx_m,
                       dy_m,
                       static_cast<std::size_t>(heights_m.shape(1)),
                       static_cast<std::size_t>(heights_m.shape(0))};
        g.validate(what.c_str());
        std::vector<float> h(heights_m.data(), heights_m.data() + heights_m.size());
        for (float& z : h) {
          if (!is_height(z)) z = std::numeric_limits<float>::quiet_NaN();
        }
        if (const std::string problem = seabed_grid_problem(g, h); !problem.empty())
          throw InputError(what + ": heights_m: " + problem);
        std::optional<Scene> built;
        try {
          built.emplace(
              GeoFrame::around(Geodetic{lat_deg * kRadPerDeg, lon_deg * kRadPerDeg, 0.0}));
        } catch (const InputError& e) {
          throw InputError(what + ": " + e.what());
        }
        Scene& scene = *built;
        scene.bathymetry = HeightGrid(g, std::move(h));
        const auto [lo, hi] = scene.bathymetry.height_range();
        if (const std::string problem = seabed_above_sea_level_problem(lo, hi); !problem.empty())
          throw InputError(what + ": heights_m: " + problem);
        scene.name = name;
        scene.objects.build_index();
        return PySimulation(SimulationSetup{.scene = std::move(scene)}, name);
      },
      py::arg("heights_m"), py::kw_only(), py::arg("x0_m") = 0.0, py::arg("y0_m") = 0.0,
      py::arg("dx_m") = 1.0, py::arg("dy_m") = -1.0, py::arg("lat_deg"), py::arg("lon_deg"),
      py::arg("name") = "python",
      "Builds a scene in code: seabed elevations `heights_m` (rows, cols; metres, up positive, "
      "NaN = hole, as is any |height| > 12000 m), node (col, row) at x = x0_m + col dx_m, y = "
      "y0_m + row dy_m in the local frame (metres; dy_m < 0 = north-up). The local frame: the "
      "UTM/UPS zone of (lat_deg, lon_deg), origin at its projection rounded to whole "
      "kilometres (scene_frame gives it; docs/python.md \"The local frame\"). Refused "
      "(ValueError): no 2 x 2 block of valid nodes, a seabed wholly above sea level, "
      "non-finite or zero spacing, lat_deg outside [-90, 90], a non-finite lon_deg. "
      "Default materials (sand everywhere), no objects, no survey lines; every option at the "
      "scene file's default. `name` stands for the file in messages.");
}

// Simulation.add_object: a primitive object of the scene file's vocabulary.
void bind_add_object(py::class_<PySimulation>& cls) {
  cls.def(
      "add_object",
      [](PySimulation& s, const py::args& args, const py::kwargs& keys) {
        // The entry of a scene file's `objects` list: add_object(type, **keys) or
        // add_object({...}, **keys).
        py::dict entry;
        if (args.size() == 1 && py::isinstance<py::dict>(args[0])) {
          entry = py::dict(args[0].cast<py::dict>());
        } else if (args.size() == 1 && py::isinstance<py::str>(args[0])) {
          entry["type"] = args[0];
        } else if (!args.empty()) {
          throw py::type_error(
              "add_object takes the object's type and the scene file's keys by name "
              "(docs/scene-format.md \"Objects\"), e.g. add_object('box', id=4, "
              "position={'east_m': 10, 'north_m': 0}, size_m=[2, 2, 1]); got " +
              std::to_string(args.size()) + " positional arguments");
        }
        for (const auto& [k, v] : keys) entry[k] = v;
        // A material index (material_index()) stands for its name.
        if (entry.contains("material") && !py::isinstance<py::str>(entry["material"]) &&
            py::hasattr(entry["material"], "__index__")) {
          const auto m = py::int_(entry["material"]).cast<long long>();
          const std::size_t n = s.scene->materials.size();
          if (m < 0 || static_cast<std::size_t>(m) >= n) {
            throw InputError(s.name + ": add_object.material = " + std::to_string(m) +
                             ". Violated constraint: a material name, or an index >= 0 and < " +
                             std::to_string(n));
          }
          entry["material"] = s.scene->materials[static_cast<std::uint16_t>(m)].name;
        }
        const yaml::Fields f(yaml_value(entry), s.name, "add_object");
        Scene& scene = s.mutable_scene();
        add_scene_object(scene, f, std::filesystem::current_path());
      },
      "Adds an object as an entry of a scene file's `objects` list would, with the same types, "
      "keys, units, defaults, checks and messages (docs/scene-format.md \"Objects\"): "
      "add_object(type, **keys) or add_object(entry_dict). Types: 'pipe' / 'cylinder' "
      "(position + length_m + heading_deg, or start + end; diameter_m), 'box' (size_m = [length, "
      "width, height]), 'rock' (size_m or diameter_m), 'wreck' (parts), 'moored' (shape, "
      "diameter_m, height_m), 'mesh' (file, scale, up_axis, face_materials); object_types() lists "
      "them with their keys and bounds. Common keys: id "
      "(> 0, unique; default: one above the largest), name, material (a name, or an index of "
      "material_index()), heading_deg, clearance_m, embed. A position is {'east_m': e, "
      "'north_m': n} in metres from the centre of the bathymetry grid (the scene file's form; "
      "that centre is the middle of bounds_m in the local frame) or {'lat_deg': .., 'lon_deg': "
      "..}. Relative file paths are relative to the current directory. A bad key or value "
      "raises ValueError naming add_object.<key>, the value and the allowed range.");
}

// Simulation.add_mesh: a triangle mesh from vertex and face arrays.
void bind_add_mesh(py::class_<PySimulation>& cls) {
  cls.def(
      "add_mesh",
      [](PySimulation& s, std::int32_t id,
         const py::array_t<double, py::array::c_style | py::array::forcecast>& vertices_m,
         const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& triangles,
         double x_m, double y_m, double heading_rad, const py::object& scale,
         std::uint16_t material, const py::object& face_materials, double clearance_m,
         double embed_fraction) {
        const std::string what = s.name + ": mesh object " + std::to_string(id);
        if (vertices_m.ndim() != 2 || vertices_m.shape(1) != 3) {
          throw InputError(what + ": vertices_m must be an (n, 3) array");
        }
        if (triangles.ndim() != 2 || triangles.shape(1) != 3) {
          throw InputError(what + ": triangles must be an (m, 3) array of vertex indices");
        }
        const std::size_t material_count = s.scene->materials.size();
        const auto check_material = [&](std::int64_t m, const std::string& field) {
          if (m < 0 || static_cast<std::uint64_t>(m) >= material_count) {
            throw InputError(what + ": " + field + " = " + std::to_string(m) +
                             ". Violated constraint: >= 0 and < " + std::to_string(material_count));
          }
          return static_cast<std::uint16_t>(m);
        };
        check_material(material, "material");
        TriangleMesh model;
        const auto v = vertices_m.unchecked<2>();
        model.vertex_m.reserve(static_cast<std::size_t>(v.shape(0)));
        for (py::ssize_t i = 0; i < v.shape(0); ++i)
          model.vertex_m.emplace_back(v(i, 0), v(i, 1), v(i, 2));
        const auto t = triangles.unchecked<2>();
        const auto vertex_count = static_cast<std::int64_t>(v.shape(0));
        model.triangle.reserve(static_cast<std::size_t>(t.shape(0)));
        for (py::ssize_t i = 0; i < t.shape(0); ++i) {
          std::array<std::uint32_t, 3> tri{};
          for (py::ssize_t k = 0; k < 3; ++k) {
            if (t(i, k) < 0 || t(i, k) >= vertex_count) {
              throw InputError(what + ": triangles[" + std::to_string(i) + "] = " +
                               std::to_string(t(i, k)) + ". Violated constraint: >= 0 and < " +
                               std::to_string(vertex_count) + " (the number of vertices)");
            }
            tri[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(t(i, k));
          }
          model.triangle.push_back(tri);
        }
        if (face_materials.is_none()) {
          model.material.assign(model.triangle.size(), material);
        } else {
          const auto fm =
              face_materials
                  .cast<py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>>();
          if (fm.ndim() != 1 || static_cast<std::size_t>(fm.shape(0)) != model.triangle.size()) {
            throw InputError(what + ": face_materials must hold one material per triangle (" +
                             std::to_string(model.triangle.size()) + ")");
          }
          for (py::ssize_t i = 0; i < fm.shape(0); ++i) {
            model.material.push_back(
                check_material(fm.at(i), "face_materials[" + std::to_string(i) + "]"));
          }
        }
        MeshPlacement where;
        where.position_xy_m = {x_m, y_m};
        where.heading_rad = heading_rad;
        where.clearance_m = clearance_m;
        where.embed_fraction = embed_fraction;
        if (py::isinstance<py::float_>(scale) || py::isinstance<py::int_>(scale)) {
          const double k = scale.cast<double>();
          where.scale = {k, k, k};
        } else {
          const auto k = scale.cast<std::array<double, 3>>();
          where.scale = {k[0], k[1], k[2]};
        }
        // The bounds and message of a scene file's mesh scale (the object table).
        const ObjectParam& bound = *find_object_type("mesh")->param("scale");
        if (!bound.accepts(where.scale.x()) || !bound.accepts(where.scale.y()) ||
            !bound.accepts(where.scale.z())) {
          throw InputError(what + ": scale = (" + std::to_string(where.scale.x()) + ", " +
                           std::to_string(where.scale.y()) + ", " +
                           std::to_string(where.scale.z()) +
                           "). Violated constraint: " + bound.constraint());
        }
        Scene& scene = s.mutable_scene();
        scene.objects.add(
            place_mesh(std::move(model), where, scene.bathymetry, id, material, what));
        scene.objects.build_index();
      },
      py::arg("id"), py::arg("vertices_m"), py::arg("triangles"), py::kw_only(), py::arg("x_m"),
      py::arg("y_m"), py::arg("heading_rad") = 0.0, py::arg("scale") = py::float_(1.0),
      py::arg("material") = 0, py::arg("face_materials") = py::none(), py::arg("clearance_m") = 0.0,
      py::arg("embed_fraction") = 0.0,
      "Adds a triangle mesh object (docs/scene-format.md \"mesh\"): vertices_m (n, 3) in the "
      "model frame (x forward along heading_rad, y to port, z up; metres), triangles (m, 3) "
      "vertex indices wound counter-clockwise seen from outside; id > 0 (its label in the "
      "truth). The model is scaled (one number or (x, y, z)), turned to heading_rad (azimuth of "
      "the model x axis clockwise from grid north), its origin put at (x_m, y_m) in the local "
      "frame and its lowest point on the seabed there, plus clearance_m (moored or floating) or "
      "sunk by embed_fraction of its height. material = index into the scene's material table; "
      "face_materials, one index per triangle, overrides it face by face. Mesh files: a scene "
      "file's `type: mesh` (from_yaml), or read them with any Python mesh library.");
}

// Simulation.add_line, survey_poses and make_poses: the survey and its poses.
void bind_survey(py::class_<PySimulation>& cls) {
  cls.def(
      "add_line",
      [](PySimulation& s, const std::string& line_name,
         py::array_t<double, py::array::c_style | py::array::forcecast> waypoints_xy_m) {
        const std::string what = s.name + ": survey line '" + line_name + "'";
        if (waypoints_xy_m.ndim() != 2 || waypoints_xy_m.shape(1) != 2) {
          std::string shape;
          for (py::ssize_t d = 0; d < waypoints_xy_m.ndim(); ++d)
            shape += (d ? ", " : "") + std::to_string(waypoints_xy_m.shape(d));
          throw InputError(what + ": waypoints_xy_m has shape (" + shape +
                           "). Violated constraint: shape (n, 2), n >= 2");
        }
        SurveyLine l{line_name, {}};
        const auto w = waypoints_xy_m.unchecked<2>();
        for (py::ssize_t i = 0; i < w.shape(0); ++i)
          l.waypoints_xy_m.emplace_back(w(i, 0), w(i, 1));
        check_survey_line(*s.scene, l, s.name);
        s.setup.lines.push_back(std::move(l));
        try {
          (void)s.setup.make_survey();
        } catch (const InputError& e) {
          s.setup.lines.pop_back();
          throw InputError(s.name + ": " + e.what());
        } catch (...) {
          s.setup.lines.pop_back();
          throw;
        }
        s.invalidate();
      },
      py::arg("name"), py::arg("waypoints_xy_m"),
      "Adds a survey line: waypoints (n, 2), n >= 2, in the local frame, metres (a scene file's "
      "east_m/north_m: scene_frame.local_from_scene), followed at survey.speed_m_s. Refused "
      "(ValueError naming the waypoint): a non-finite waypoint, one more than 1e6 m from the "
      "grid's centre, a repeated one.");

  cls.def(
      "survey_poses",
      [](PySimulation& s) {
        const Survey sv = s.survey();
        const auto n = static_cast<py::ssize_t>(sv.total_pings());
        py::array_t<PoseRecord> out(n);
        PoseRecord* r = out.mutable_data();
        const Scene& scene = *s.scene;
        py::gil_scoped_release release;
        for (py::ssize_t i = 0; i < n; ++i) {
          r[i] = record_of(sv.pose(static_cast<std::uint64_t>(i), scene.bathymetry));
        }
        return out;
      },
      "Every ping pose of the survey, in order (numpy array of POSE_DTYPE: positions in the "
      "local frame in metres, angles in radians, time in microseconds since 1970 UTC, "
      "ping_index = the noise key), the poses `run_simulation` renders.");
  cls.def(
      "make_poses",
      [](const PySimulation& s, const py::array_t<double, py::array::forcecast>& x_m,
         const py::array_t<double, py::array::forcecast>& y_m,
         const py::array_t<double, py::array::forcecast>& z_m,
         const py::array_t<double, py::array::forcecast>& heading_rad,
         const py::array_t<double, py::array::forcecast>& pitch_rad,
         const py::array_t<double, py::array::forcecast>& roll_rad, std::uint64_t first_noise_key) {
        // Every array 1-D (or a scalar) of one length n, or of length 1 (broadcast).
        const std::pair<const char*, const py::array_t<double, py::array::forcecast>*> args[] = {
            {"x_m", &x_m},
            {"y_m", &y_m},
            {"z_m", &z_m},
            {"heading_rad", &heading_rad},
            {"pitch_rad", &pitch_rad},
            {"roll_rad", &roll_rad}};
        py::ssize_t n = 1;
        const char* n_from = nullptr;
        for (const auto& [name, a] : args) {
          if (a->ndim() > 1) {
            throw InputError(std::string("make_poses: ") + name + " has " +
                             std::to_string(a->ndim()) +
                             " dimensions. Violated constraint: a number or a 1-D array");
          }
          if (a->size() == 1) continue;
          if (n_from && a->size() != n) {
            throw InputError(std::string("make_poses: ") + name + " has " +
                             std::to_string(a->size()) + " values, " + n_from + " has " +
                             std::to_string(n) +
                             ". Violated constraint: arrays of one length (or single values, "
                             "used for every pose)");
          }
          n = a->size();
          n_from = name;
        }
        py::array_t<PoseRecord> out(n);
        PoseRecord* r = out.mutable_data();
        for (py::ssize_t i = 0; i < n; ++i) {
          const PingPose p = sensor_pose({at(x_m, i), at(y_m, i), at(z_m, i)}, at(heading_rad, i),
                                         at(pitch_rad, i), at(roll_rad, i), s.scene->bathymetry,
                                         first_noise_key + static_cast<std::uint64_t>(i));
          check_pose(p, s.scene->bathymetry, "make_poses: pose " + std::to_string(i),
                     {"x_m", "y_m", "z_m", "heading_rad", "pitch_rad", "roll_rad"});
          r[i] = record_of(p);
        }
        return out;
      },
      py::arg("x_m"), py::arg("y_m"), py::arg("z_m"), py::arg("heading_rad") = 0.0,
      py::arg("pitch_rad") = 0.0, py::arg("roll_rad") = 0.0, py::arg("first_noise_key") = 0,
      "Poses outside a survey (POSE_DTYPE): sensor positions in the local frame (metres, z on "
      "the bathymetry's datum, up positive), heading clockwise from grid north, pitch + nose "
      "up, roll + starboard down (radians); scalars broadcast. The altitude is taken from the "
      "seabed; pose i gets noise key first_noise_key + i. Arrays of different lengths and "
      "poses that render_poses would refuse raise ValueError naming the argument.");
}

// The read-only properties of the scene and its calibration, and material_index.
void bind_properties(py::class_<PySimulation>& cls) {
  cls.def_property_readonly(
      "name", [](const PySimulation& s) { return s.scene->name; }, "The scene's name.");
  cls.def_property_readonly(
      "bounds_m",
      [](const PySimulation& s) {
        const Eigen::Vector4d b = s.scene->bathymetry.bounds();
        return py::make_tuple(b[0], b[1], b[2], b[3]);
      },
      "Bathymetry node area in the local frame: (min x, min y, max x, max y), metres.");
  cls.def_property_readonly(
      "epsg", [](const PySimulation& s) { return s.scene->frame.epsg(); },
      "EPSG code of the scene's UTM/UPS frame.");
  cls.def_property_readonly(
      "object_count", [](const PySimulation& s) { return s.scene->objects.primitives().size(); },
      "Number of object primitives in the scene.");
  cls.def_property_readonly(
      "samples_per_side",
      [](const PySimulation& s) { return s.setup.config.sonar.samples_per_channel; },
      "Samples per side of a rendered ping (sonar.samples).");
  cls.def_property_readonly(
      "gain_db", [](PySimulation& s) { return s.simulator()->gain_db(); },
      "Quantiser gain of the global calibration, dB.");
  cls.def_property_readonly(
      "absorption_db_per_m", [](PySimulation& s) { return s.simulator()->absorption_db_per_m(); },
      "Absorption of the configuration, dB per metre (one way).");
  cls.def_property_readonly(
      "along_track_planes", [](PySimulation& s) { return s.simulator()->along_track().planes; },
      "Along-track planes per ping side the renderer uses (chosen automatically or set).");
  cls.def(
      "material_index",
      [](const PySimulation& s, const std::string& material_name) {
        try {
          return s.scene->materials.index_of(material_name);
        } catch (const InputError& e) {
          throw InputError(s.name + ": " + e.what());
        }
      },
      py::arg("name"),
      "Index of a material of the scene's table by name (the built-in mud, sand, gravel, rock, "
      "steel, concrete, or the scene file's own), for add_object and add_mesh.");
}

}  // namespace

void bind_simulation(py::module_&, py::class_<PySimulation>& cls) {
  bind_constructors(cls);
  bind_add_object(cls);
  bind_add_mesh(cls);
  bind_survey(cls);
  bind_properties(cls);
}

}  // namespace sonarsynth::python
