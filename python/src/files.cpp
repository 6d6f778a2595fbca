// SPDX-License-Identifier: MIT
// Files: run_simulation (a survey to XTF/JSF files and products) and XTF or JSF into numpy.
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "bindings.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/run_simulation.hpp"
#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"

namespace sonarsynth::python {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// A numpy array owning `v` (moved into the capsule: no copy), shaped `shape`.
template <class T>
py::array owned(std::vector<T>&& v, std::vector<py::ssize_t> shape) {
  auto* held = new std::vector<T>(std::move(v));
  py::capsule owner(held, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, held->data(), owner);
}

// The samples of one side, ping after ping, without padding: the memory is the file's samples
// (4 bytes each) whatever the ping lengths.
struct Rows {
  std::vector<float> data;
  std::vector<std::uint32_t> lengths;
  void add(const std::vector<float>& row) {
    data.insert(data.end(), row.begin(), row.end());
    lengths.push_back(static_cast<std::uint32_t>(row.size()));
  }
  // (pings, samples) if every ping has the same length, else a list of 1-D arrays, one per ping,
  // that view one buffer (docs/python.md, "Files").
  py::object arrays() && {
    const auto n = static_cast<py::ssize_t>(lengths.size());
    const bool equal = std::all_of(lengths.begin(), lengths.end(),
                                   [&](std::uint32_t l) { return l == lengths.front(); });
    if (equal) {
      const py::ssize_t width = n == 0 ? 0 : lengths.front();
      return owned(std::move(data), {n, width});
    }
    const auto total = static_cast<py::ssize_t>(data.size());
    const py::array flat = owned(std::move(data), {total});
    py::list out(static_cast<std::size_t>(n));
    py::ssize_t start = 0;
    for (py::ssize_t i = 0; i < n; ++i) {
      const py::ssize_t end = start + lengths[static_cast<std::size_t>(i)];
      out[static_cast<std::size_t>(i)] = flat[py::slice(start, end, 1)];
      start = end;
    }
    return out;
  }
};

// The pings of a sonar file of any format as numpy arrays; `expected` refuses the others.
py::dict read_sidescan(const std::filesystem::path& path, const SonarFormat* expected) {
  Rows port, stbd;
  std::vector<std::int64_t> time_us;
  std::vector<std::uint32_t> ping_number;
  std::vector<double> lat, lon, ship_lat, ship_lon, heading, pitch, roll, heave, altitude, depth,
      speed, sound_speed, slant_range;
  std::vector<std::uint8_t> nav_valid, time_valid;
  std::vector<std::string> anomalies;
  std::string format;
  {
    py::gil_scoped_release release;
    if (expected && identify_sonar_format(path) != expected) {
      // "an XTF", "a JSF": the article of the name's first letter as spoken.
      const std::string_view name = expected->display_name;
      const bool an = std::string_view("AEFHILMNORSX").find(name.front()) != std::string_view::npos;
      throw FormatError(path.string() + ": not " + (an ? "an " : "a ") + std::string(name) +
                        " file (read_sonar reads any of " + sonar_format_names() + ")");
    }
    const std::unique_ptr<SideScanSource> source = SideScanSource::open(path);
    format = source->format().name;
    SideScanRecord r;
    while (source->next(r)) {
      const SonarPing& s = r.sonar;
      port.add(s.port);
      stbd.add(s.starboard);
      time_us.push_back(s.time_utc.time_since_epoch().count());
      ping_number.push_back(s.ping_number);
      lat.push_back(s.sensor_position.lat_rad * kDegPerRad);
      lon.push_back(s.sensor_position.lon_rad * kDegPerRad);
      const Geodetic ship = s.ship_position.value_or(s.sensor_position);
      ship_lat.push_back(ship.lat_rad * kDegPerRad);
      ship_lon.push_back(ship.lon_rad * kDegPerRad);
      heading.push_back(s.heading_true_rad);
      pitch.push_back(s.pitch_rad);
      roll.push_back(s.roll_rad);
      heave.push_back(s.heave_m);
      altitude.push_back(s.altitude_m);
      depth.push_back(s.depth_m);
      speed.push_back(s.speed_m_s);
      sound_speed.push_back(s.sound_speed_m_s);
      slant_range.push_back(s.slant_range_m);
      nav_valid.push_back(r.nav_valid ? 1 : 0);
      time_valid.push_back(r.time_valid ? 1 : 0);
    }
    anomalies = source->anomaly_messages(std::numeric_limits<std::size_t>::max());
  }
  const auto n = static_cast<py::ssize_t>(time_us.size());
  py::dict d;
  d["format"] = format;
  d["port_sample_count"] = owned(std::vector<std::uint32_t>(port.lengths), {n});
  d["starboard_sample_count"] = owned(std::vector<std::uint32_t>(stbd.lengths), {n});
  d["port"] = std::move(port).arrays();
  d["starboard"] = std::move(stbd).arrays();
  d["time_utc_us"] = owned(std::move(time_us), {n});
  d["ping_number"] = owned(std::move(ping_number), {n});
  d["sensor_lat_deg"] = owned(std::move(lat), {n});
  d["sensor_lon_deg"] = owned(std::move(lon), {n});
  d["ship_lat_deg"] = owned(std::move(ship_lat), {n});
  d["ship_lon_deg"] = owned(std::move(ship_lon), {n});
  d["heading_rad"] = owned(std::move(heading), {n});
  d["pitch_rad"] = owned(std::move(pitch), {n});
  d["roll_rad"] = owned(std::move(roll), {n});
  d["heave_m"] = owned(std::move(heave), {n});
  d["altitude_m"] = owned(std::move(altitude), {n});
  d["depth_m"] = owned(std::move(depth), {n});
  d["speed_m_s"] = owned(std::move(speed), {n});
  d["sound_speed_m_s"] = owned(std::move(sound_speed), {n});
  d["slant_range_m"] = owned(std::move(slant_range), {n});
  d["nav_valid"] = owned(std::move(nav_valid), {n}).attr("astype")("bool");
  d["time_valid"] = owned(std::move(time_valid), {n}).attr("astype")("bool");
  d["anomalies"] = anomalies;
  return d;
}

// sonarsynth.run_simulation: a scene file to its output directory, as `sonarsynth simulate`.
void bind_run(py::module_& m) {
  m.def(
      "run_simulation",
      [](const std::filesystem::path& scene_path, const std::filesystem::path& out_dir,
         std::optional<std::uint64_t> seed, std::optional<double> range_m,
         std::optional<std::size_t> samples, std::optional<unsigned> threads,
         std::optional<std::string> quality, bool overwrite, bool mosaic, bool waterfalls,
         bool truth, double mosaic_pixel_m, const py::object& progress) {
        RunOptions o;
        o.overrides.seed = seed;
        o.overrides.range_m = range_m;
        o.overrides.samples = samples;
        o.overrides.threads = threads;
        o.overrides.quality = std::move(quality);
        o.overwrite = overwrite;
        o.products.mosaic = mosaic;
        o.products.waterfalls = waterfalls;
        o.products.truth = truth;
        o.products.mosaic_pixel_m = mosaic_pixel_m;
        if (!progress.is_none()) {
          o.progress = [&progress](std::uint64_t done, std::uint64_t total) {
            py::gil_scoped_acquire gil;
            progress(done, total);
          };
        }
        RunResult r;
        {
          py::gil_scoped_release release;
          r = run_simulation(scene_path.string(), out_dir, o);
        }
        py::dict d;
        py::list files;
        for (const auto& f : r.files) files.append(f.string());
        d["files"] = files;
        d["line_names"] = r.line_names;
        d["total_pings"] = r.total_pings;
        d["warnings"] = r.warnings;
        d["compatibility_warnings"] = r.compatibility_warnings;
        d["notes"] = r.notes;
        d["gain_db"] = r.gain_db;
        d["along_track_planes"] = r.along_track.planes;
        d["run_s"] = r.run_s;
        d["products_s"] = r.products_s;
        d["total_s"] = r.total_s;
        d["cpu_s"] = r.cpu_s;
        return d;
      },
      py::arg("scene_path"), py::arg("out_dir"), py::kw_only(), py::arg("seed") = py::none(),
      py::arg("range_m") = py::none(), py::arg("samples") = py::none(),
      py::arg("threads") = py::none(), py::arg("quality") = py::none(),
      py::arg("overwrite") = false, py::arg("mosaic") = true, py::arg("waterfalls") = true,
      py::arg("truth") = true, py::arg("mosaic_pixel_m") = kDefaultMosaicPixelM,
      py::arg("progress") = py::none(),
      "Everything `sonarsynth simulate SCENE -o OUT_DIR` does: one XTF file per survey line, "
      "the mosaics (mosaic_pixel_m: pixel size, metres), waterfalls and truth products, "
      "effective.yaml; the directory appears only when all is written. Overrides as the CLI's "
      "(--seed, --range in metres, --samples per side, --threads, --quality). progress(done, "
      "total) is called after each block of pings. Returns a dict: files, line_names, "
      "total_pings, warnings, compatibility_warnings, notes, gain_db, along_track_planes, "
      "run_s (rendering and products, which overlap) / products_s (mosaic files) / total_s "
      "(wall seconds), cpu_s (process CPU seconds).");
}

// sonarsynth.read_xtf, read_jsf and read_sonar: a sonar file's pings into numpy.
void bind_readers(py::module_& m) {
  // One format or any (detected from the file's first bytes): the same arrays.
  const auto reader = [](const SonarFormat* expected) {
    return [expected](const std::filesystem::path& path) { return read_sidescan(path, expected); };
  };
  const std::string arrays =
      "port and starboard float32 samples, NEAR -> FAR: a (pings, samples) array when every "
      "ping of the side has the same number of samples, else a list of 1-D arrays, one per "
      "ping (never padded); port_sample_count / starboard_sample_count (pings,) give each "
      "ping's length either way; and per ping time_utc_us (microseconds since 1970 UTC), "
      "ping_number, "
      "sensor_lat_deg / sensor_lon_deg and ship_lat_deg / ship_lon_deg (WGS 84, degrees), "
      "heading_rad (true, clockwise from north), pitch_rad (+ nose up), roll_rad (+ starboard "
      "down), heave_m (+ up), altitude_m, depth_m (+ down), speed_m_s, sound_speed_m_s, "
      "slant_range_m, nav_valid, time_valid; format ('xtf' or 'jsf'); anomalies: the reader's "
      "messages about broken records (it skips them and carries on). Raises FormatError if the "
      "file cannot be read.";
  m.def("read_xtf", reader(find_sonar_format("xtf")), py::arg("path"),
        ("Reads the sonar pings of an XTF file (any sonar; times in 1/100 s) into numpy: " + arrays)
            .c_str());
  m.def("read_jsf", reader(find_sonar_format("jsf")), py::arg("path"),
        ("Reads the side-scan pings of an EdgeTech JSF file (the first side-scan subsystem; "
         "docs/jsf.md) into numpy: " +
         arrays)
            .c_str());
  m.def("read_sonar", reader(nullptr), py::arg("path"),
        ("Reads a sonar file of any known format (sonarsynth.formats(); the format detected "
         "from its first bytes) into numpy: " +
         arrays)
            .c_str());
}

// sonarsynth.formats and info: the format list and a file's summary.
void bind_format_info(py::module_& m) {
  // The format list (formats/registry/sonar_formats.cpp), as `sonarsynth info` and `simulate` see
  // it.
  m.def(
      "formats",
      [] {
        py::list out;
        for (const SonarFormat* f : sonar_formats()) {
          py::dict d;
          d["name"] = std::string(f->name);
          d["display_name"] = std::string(f->display_name);
          d["description"] = std::string(f->description);
          py::list ext;
          for (std::string_view e : f->extensions) ext.append(std::string(e));
          d["extensions"] = ext;
          d["read"] = f->capabilities.read;
          d["simulate"] = f->capabilities.simulate;
          py::list conversions;
          for (const SonarConversion& c : f->conversions) {
            conversions.append(py::make_tuple(std::string(c.from), std::string(c.to)));
          }
          d["conversions"] = conversions;
          out.append(d);
        }
        return out;
      },
      "The sonar formats sonarsynth knows, in the order of its format list: a list of dicts "
      "with name ('xtf', the key of output.formats and of read_sonar's 'format'), display_name, "
      "description, extensions (lower case, with the dot), read (read_sonar and info read it), "
      "simulate (simulate writes it: output.formats) and conversions ((from, to) name pairs "
      "that convert provides).");
  m.def(
      "info",
      [](const std::filesystem::path& path, std::size_t max_anomalies) {
        SonarFileInfo info;
        {
          py::gil_scoped_release release;
          info = sonar_file_info(path, max_anomalies);
        }
        py::dict d;
        d["json"] = info.json;
        d["text"] = info.text;
        d["summary"] = py::module_::import("json").attr("loads")(info.json);
        return d;
      },
      py::arg("path"), py::arg("max_anomalies") = 20,
      "What `sonarsynth info PATH` prints, from the same library call: a dict with summary (the "
      "parsed JSON of `info --json`), json (that text) and text (the text output, listing at "
      "most max_anomalies anomaly messages). The format is detected from the file's first "
      "bytes. Raises FormatError if the file cannot be read.");
}

}  // namespace

void bind_files(py::module_& m) {
  bind_run(m);
  bind_readers(m);
  bind_format_info(m);
}

}  // namespace sonarsynth::python
