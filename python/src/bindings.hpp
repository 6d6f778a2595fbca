// SPDX-License-Identifier: MIT
// Internal to the Python module: the pieces module.cpp assembles (docs/python.md).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
// Every path argument is a std::filesystem::path: pybind11's caster takes str and os.PathLike.
#include <pybind11/stl/filesystem.h>
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <memory>
#include <string>

#include "sonarsynth/formats/config/simulation_file.hpp"
#include "sonarsynth/scene.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth::python {

namespace py = pybind11;

/// One ping pose as a numpy record (sonarsynth.POSE_DTYPE): PingPose's fields, SI units.
struct PoseRecord {
  std::uint64_t line;
  std::uint64_t ping_in_line;
  std::uint64_t ping_index;  ///< noise key
  std::int64_t time_utc_us;  ///< microseconds since 1970-01-01T00:00:00Z
  double sensor_x_m, sensor_y_m, sensor_z_m;
  double reference_x_m, reference_y_m;
  double heading_rad, pitch_rad, roll_rad;
  double heave_m, altitude_m, speed_m_s, along_track_m;
};

PoseRecord record_of(const PingPose& p);
PingPose pose_of(const PoseRecord& r);

/// A simulation being configured and rendered from Python: the settings of a scene file
/// (SimulationSetup, its scene moved out) and the scene, shared copy-on-write with the Simulator
/// built from them (rebuilt after a change).
class PySimulation {
 public:
  PySimulation(SimulationSetup setup, std::string name);

  /// Names the file in validation messages ("scene.yaml: sonar.range_m = ...").
  std::string name;
  SimulationSetup setup;  ///< scene moved out into `scene`
  std::shared_ptr<Scene> scene;

  /// The Simulator of the current settings (built on first use, with the GIL released).
  std::shared_ptr<const Simulator> simulator();
  /// Drops the Simulator (after a change of the settings).
  void invalidate() { sim_.reset(); }
  /// The scene, copied first if a Simulator still shares it (copy on write).
  Scene& mutable_scene();
  Survey survey() const;

 private:
  std::shared_ptr<const Simulator> sim_;
};

/// The YAML a scene file would hold for `value`: Python's repr of a number (shortest round
/// trip, so the double read back is the same), true/false, a string or os.PathLike as its text,
/// a dict as a map and a sequence (list, tuple, 1-D array) as a list. Defined in options.cpp.
YAML::Node yaml_value(const py::handle& value);

void bind_options(py::module_& m, py::class_<PySimulation>& cls);
void bind_simulation(py::module_& m, py::class_<PySimulation>& cls);
void bind_frame(py::module_& m, py::class_<PySimulation>& cls);
void bind_render(py::module_& m, py::class_<PySimulation>& cls);
void bind_files(py::module_& m);
void bind_dataset(py::module_& m);
void bind_object_types(py::module_& m);
void bind_products(py::module_& m);

}  // namespace sonarsynth::python
