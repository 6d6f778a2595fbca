// SPDX-License-Identifier: MIT
// The Python module `sonarsynth` (docs/python.md).
#include <pybind11/pybind11.h>

#include <string>

#include "bindings.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/simd.hpp"
#include "sonarsynth/version.hpp"

namespace py = pybind11;
using sonarsynth::python::PoseRecord;

PYBIND11_MODULE(_sonarsynth, m) {
  m.doc() =
      "Synthetic side-scan sonar: load or build a scene, configure it with the scene file's "
      "option names, render pings into numpy arrays, run surveys to XTF files and read XTF "
      "back. Units: metres, seconds, radians (names end in _m, _s, _rad; options keep the scene "
      "file's units, e.g. sonar.tilt_deg). See docs/python.md.";
  m.attr("__version__") = sonarsynth::kVersion;

  // Invalid input (InputError) is a ValueError with the C++ message; unreadable or malformed
  // files (FormatError) are sonarsynth.FormatError, an OSError.
  py::register_exception<sonarsynth::FormatError>(m, "FormatError", PyExc_OSError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const sonarsynth::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  // The vector kernels' instruction set (the CLI's SONARSYNTH_SIMD, docs/benchmarks.md).
  sonarsynth::simd::configure_from_environment();
  m.def(
      "simd_target",
      []() {
        return std::string(sonarsynth::simd::target_name(sonarsynth::simd::active_target()));
      },
      "The instruction set the vector kernels run now: 'avx512', 'avx2' or 'scalar'.");
  m.def(
      "set_simd_target",
      [](const std::string& name) {
        sonarsynth::simd::set_target(sonarsynth::simd::parse_target(name, "set_simd_target"));
      },
      py::arg("name"),
      "Caps the vector kernels at 'avx512', 'avx2' or 'scalar' ('auto': the best the CPU runs), "
      "for the whole process; how far the paths agree is stated in docs/benchmarks.md. A target "
      "the CPU lacks raises ValueError.");

  PYBIND11_NUMPY_DTYPE(PoseRecord, line, ping_in_line, ping_index, time_utc_us, sensor_x_m,
                       sensor_y_m, sensor_z_m, reference_x_m, reference_y_m, heading_rad, pitch_rad,
                       roll_rad, heave_m, altitude_m, speed_m_s, along_track_m);
  m.attr("POSE_DTYPE") = py::dtype::of<PoseRecord>();
  m.attr("SAMPLE_CLASSES") =
      py::make_tuple("water_column", "seabed", "object", "shadow", "no_seabed");

  py::class_<sonarsynth::python::PySimulation> cls(
      m, "Simulation",
      "A scene with its simulation settings (the sections of a scene file). Create it with "
      "Simulation.from_file, Simulation.from_yaml or Simulation.from_heights; configure it with "
      "set(); render with render_ping / render_poses.");
  sonarsynth::python::bind_options(m, cls);
  sonarsynth::python::bind_simulation(m, cls);
  sonarsynth::python::bind_frame(m, cls);
  sonarsynth::python::bind_render(m, cls);
  sonarsynth::python::bind_files(m);
  sonarsynth::python::bind_dataset(m);
  sonarsynth::python::bind_object_types(m);
  sonarsynth::python::bind_products(m);
}
