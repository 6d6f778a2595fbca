// SPDX-License-Identifier: MIT
// Rendering into numpy: one ping (arrays that own the renderer's buffers, no copy; the ground
// positions computed from the float ground ranges) or a batch of poses (preallocated arrays
// filled by worker threads), the GIL released while rendering.
#include <pybind11/stl.h>

#include <algorithm>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "sonarsynth/error.hpp"

namespace sonarsynth::python {

namespace {

// A 1-D array viewing `v` (no copy); `owner` keeps the storage alive.
template <class T, class V>
py::array view(const V& v, const py::capsule& owner) {
  return py::array_t<T>({static_cast<py::ssize_t>(v.size())}, {static_cast<py::ssize_t>(sizeof(T))},
                        reinterpret_cast<const T*>(v.data()), owner);
}

py::dict side_dict(const SideOutput& s, const py::capsule& owner) {
  py::dict d;
  d["samples"] = view<float>(s.samples, owner);
  if (!s.clean_samples.empty()) d["clean_samples"] = view<float>(s.clean_samples, owner);
  if (!s.truth_class.empty()) {
    d["truth_class"] = view<std::uint8_t>(s.truth_class, owner);
    d["object_id"] = view<std::int32_t>(s.truth_label, owner);
    d["grazing_rad"] = view<float>(s.truth_grazing_rad, owner);
    // The ground positions are derived here from the float ground ranges (docs/python.md).
    const auto n = static_cast<py::ssize_t>(s.truth_ground_range_m.size());
    py::array_t<double> x(n), y(n);
    s.truth_ground_positions(x.mutable_data(), y.mutable_data());
    d["ground_x_m"] = x;
    d["ground_y_m"] = y;
  }
  d["saturated"] = s.saturated;
  d["invalid"] = s.invalid;
  return d;
}

// `poses` as a 1-D C-contiguous POSE_DTYPE array: the array itself, or a copy field by field
// (by name) of a structured array that has every field of POSE_DTYPE. Anything else, a list of
// numbers above all (numpy would cast each number into every field of a pose), is a TypeError
// or ValueError naming the argument, the dtype expected and what was given.
py::array_t<PoseRecord> pose_array(const py::object& poses, const char* fn) {
  const py::dtype want = py::dtype::of<PoseRecord>();
  const std::string expect = std::string(fn) +
                             ": poses must be a 1-D numpy structured array of "
                             "sonarsynth.POSE_DTYPE (from survey_poses() or make_poses())";
  if (!py::isinstance<py::array>(poses)) {
    throw py::type_error(expect + "; got " +
                         py::str(py::type::of(poses).attr("__name__")).cast<std::string>());
  }
  py::array a = poses.cast<py::array>();
  const py::object names = a.dtype().attr("names");
  if (names.is_none()) {
    throw py::type_error(expect + "; got an array of dtype " +
                         py::str(a.dtype()).cast<std::string>() + " (no fields)");
  }
  if (a.ndim() != 1) {
    std::string shape;
    for (py::ssize_t k = 0; k < a.ndim(); ++k) {
      shape += (k ? ", " : "") + std::to_string(a.shape(k));
    }
    throw InputError(expect + "; got an array of shape (" + shape + ")");
  }
  if (a.dtype().is(want)) {
    return py::array_t<PoseRecord, py::array::c_style | py::array::forcecast>::ensure(a);
  }
  std::string missing;
  const py::tuple have = names.cast<py::tuple>();
  for (const py::handle f : want.attr("names").cast<py::tuple>()) {
    if (!have.contains(f)) missing += (missing.empty() ? "" : ", ") + f.cast<std::string>();
  }
  if (!missing.empty()) {
    throw InputError(expect + "; got a structured array without the fields " + missing);
  }
  py::array_t<PoseRecord> copy(a.shape(0));
  for (const py::handle f : want.attr("names").cast<py::tuple>()) copy[f] = a[f];
  return copy;
}

// The output arrays of a batch: (pings, 2 sides, samples), side 0 port, 1 starboard; the
// Simulator's render_batch fills them through `buffers` (pointers taken with the GIL held).
struct Batch {
  bool truth = false, clean = false;
  py::array_t<float> samples_arr, clean_arr, grazing;
  py::array_t<std::uint8_t> truth_class;
  py::array_t<std::int32_t> object_id;
  py::array_t<double> ground_x, ground_y;
  py::array_t<std::uint32_t> saturated, invalid;
  BatchOutput buffers;

  // A new array of `shape`, or out[key] (a previous result) if `out` is given: checked to be a
  // writeable C-contiguous array of the right type and shape, filled in place.
  template <class T>
  static py::array_t<T> take(const py::object& out, const char* key,
                             const std::vector<py::ssize_t>& shape) {
    if (out.is_none()) return py::array_t<T>(shape);
    const py::dict d = out.cast<py::dict>();
    if (!d.contains(key)) throw InputError(std::string("render_poses: out has no '") + key + "'");
    const py::array a = d[key].cast<py::array>();
    const bool ok = a.dtype().is(py::dtype::of<T>()) && a.writeable() &&
                    (a.flags() & py::array::c_style) &&
                    a.ndim() == static_cast<py::ssize_t>(shape.size()) &&
                    std::equal(shape.begin(), shape.end(), a.shape());
    if (!ok) {
      throw InputError(std::string("render_poses: out['") + key +
                       "'] must be a writeable C-contiguous " +
                       py::str(py::dtype::of<T>()).cast<std::string>() +
                       " array of the result's shape (a previous result for as many poses)");
    }
    return a.cast<py::array_t<T>>();
  }

  Batch(std::size_t pings, std::size_t samples, bool t, bool c, const py::object& out)
      : truth(t), clean(c) {
    const std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(pings), 2,
                                         static_cast<py::ssize_t>(samples)};
    samples_arr = take<float>(out, "samples", shape);
    buffers.samples = samples_arr.mutable_data();
    if (clean) {
      clean_arr = take<float>(out, "clean_samples", shape);
      buffers.clean_samples = clean_arr.mutable_data();
    }
    if (truth) {
      truth_class = take<std::uint8_t>(out, "truth_class", shape);
      object_id = take<std::int32_t>(out, "object_id", shape);
      grazing = take<float>(out, "grazing_rad", shape);
      ground_x = take<double>(out, "ground_x_m", shape);
      ground_y = take<double>(out, "ground_y_m", shape);
      static_assert(sizeof(SampleClass) == sizeof(std::uint8_t));
      buffers.truth_class = reinterpret_cast<SampleClass*>(truth_class.mutable_data());
      buffers.object_id = object_id.mutable_data();
      buffers.grazing_rad = grazing.mutable_data();
      buffers.ground_x_m = ground_x.mutable_data();
      buffers.ground_y_m = ground_y.mutable_data();
    }
    const std::vector<py::ssize_t> counts{static_cast<py::ssize_t>(pings), 2};
    saturated = take<std::uint32_t>(out, "saturated", counts);
    invalid = take<std::uint32_t>(out, "invalid", counts);
    buffers.saturated = saturated.mutable_data();
    buffers.invalid = invalid.mutable_data();
  }

  py::dict result() const {
    py::dict d;
    d["samples"] = samples_arr;
    if (clean) d["clean_samples"] = clean_arr;
    if (truth) {
      d["truth_class"] = truth_class;
      d["object_id"] = object_id;
      d["grazing_rad"] = grazing;
      d["ground_x_m"] = ground_x;
      d["ground_y_m"] = ground_y;
    }
    d["saturated"] = saturated;
    d["invalid"] = invalid;
    return d;
  }
};

}  // namespace

void bind_render(py::module_&, py::class_<PySimulation>& cls) {
  cls.def(
      "render_ping",
      [](PySimulation& s, double x_m, double y_m, double z_m, double heading_rad, double pitch_rad,
         double roll_rad, std::optional<std::uint64_t> noise_key) {
        const std::shared_ptr<const Simulator> sim = s.simulator();
        const PingPose pose = sensor_pose({x_m, y_m, z_m}, heading_rad, pitch_rad, roll_rad,
                                          sim->scene().bathymetry, noise_key);
        check_pose(pose, sim->scene().bathymetry, "render_ping",
                   {"x_m", "y_m", "z_m", "heading_rad", "pitch_rad", "roll_rad"});
        auto* ping = new RenderedPing;
        py::capsule owner(ping, [](void* p) { delete static_cast<RenderedPing*>(p); });
        {
          py::gil_scoped_release release;
          auto ws = sim->make_workspace();
          sim->render_ping(pose, *ws, *ping);
        }
        py::dict d;
        d["port"] = side_dict(ping->port, owner);
        d["starboard"] = side_dict(ping->starboard, owner);
        py::array_t<PoseRecord> rendered_pose(1);
        rendered_pose.mutable_data()[0] = record_of(ping->pose);
        d["pose"] = rendered_pose;
        return d;
      },
      py::arg("x_m"), py::arg("y_m"), py::arg("z_m"), py::arg("heading_rad") = 0.0,
      py::arg("pitch_rad") = 0.0, py::arg("roll_rad") = 0.0, py::arg("noise_key") = py::none(),
      "Renders one ping with the sensor at (x_m, y_m, z_m) in the local frame (metres, z on the "
      "bathymetry datum, up positive), heading clockwise from grid north, pitch + nose up, roll "
      "+ starboard down (radians). noise_key: the ping's noise (None: a fresh one). Returns "
      "{'port': side, 'starboard': side, 'pose': POSE_DTYPE array of 1}; a side is a dict of "
      "arrays, samples NEAR -> FAR, viewing the renderer's own buffers (no copy): samples "
      "(float32, output units after TVG and quantisation), clean_samples (noise-free, if "
      "clean_samples is on), truth_class (uint8, SAMPLE_CLASSES), object_id (int32: object id, "
      "0 seabed, -1 none), grazing_rad (float32, NaN where no seabed), ground_x_m / ground_y_m "
      "(float64, local frame, NaN where none), saturated and invalid counts. The pose is "
      "checked as render_poses checks its poses (ValueError naming the argument).");

  cls.def(
      "render_poses",
      [](PySimulation& s, const py::object& poses_arg, unsigned threads, const py::object& out) {
        const py::array_t<PoseRecord> poses = pose_array(poses_arg, "render_poses");
        const std::shared_ptr<const Simulator> sim = s.simulator();
        const SimulationConfig& cfg = sim->config();
        const auto n = static_cast<std::size_t>(poses.shape(0));
        Batch batch(n, cfg.sonar.samples_per_channel, cfg.truth, cfg.clean_samples, out);
        const PoseRecord* in = poses.data();
        {
          py::gil_scoped_release release;
          sim->render_batch(
              n, [in](std::size_t i) { return pose_of(in[i]); }, batch.buffers, threads,
              "render_poses: poses");
        }
        return batch.result();
      },
      py::arg("poses"), py::kw_only(), py::arg("threads") = 0, py::arg("out") = py::none(),
      "Renders a batch of poses (a POSE_DTYPE array: survey_poses() or make_poses()) on "
      "`threads` threads (0: the configuration's, i.e. all cores by default; the output does "
      "not depend on it). Returns a dict of arrays of shape (pings, 2, samples), side 0 = port, "
      "1 = starboard, samples NEAR -> FAR, allocated once and filled in place: samples, "
      "clean_samples (if on), truth_class, object_id, grazing_rad, ground_x_m, ground_y_m (as "
      "render_ping), and saturated / invalid counts of shape (pings, 2). out: a previous result "
      "for as many poses, whose arrays are filled again in place and returned (no allocation: "
      "the fastest way to render batch after batch). Every pose is checked before any is "
      "rendered (docs/python.md \"Pose checks\"): a non-finite position or heading, |pitch| or "
      "|roll| beyond 89 deg, a sensor under the seabed or above the sea surface raise ValueError "
      "naming poses[i], the field, the value and the allowed range; poses that are not a "
      "POSE_DTYPE array raise TypeError / ValueError.");
}

}  // namespace sonarsynth::python
