// SPDX-License-Identifier: MIT
// sonarsynth.mosaic(): `sonarsynth mosaic` from the same library call (docs/python.md).
#include <pybind11/stl.h>

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/products/mosaic_files.hpp"

namespace sonarsynth::python {

namespace {

py::dict mosaic(const std::vector<std::filesystem::path>& inputs,
                const std::filesystem::path& output, double pixel_size_m, const std::string& rule,
                double taper, const std::optional<std::filesystem::path>& bathymetry,
                bool depth_positive, bool layback, const std::string& altitude_source,
                bool nadir_fill, const std::string& gain_normalisation, std::uint64_t max_pixels,
                bool count, const std::string& format,
                const std::map<std::string, std::string>& creation_options,
                const std::optional<std::filesystem::path>& rgb_path, bool rgb, bool grey,
                std::optional<double> linear, bool overwrite) {
  MosaicRequest q;
  q.names = {"output", "rgb_path", "bathymetry", "depth_positive"};
  q.inputs = inputs;
  q.output = output;
  XtfMosaicOptions& mo = q.options;
  mo.pixel_size_m = pixel_size_m;
  mo.gridding.rule = parse_mosaic_rule(rule, "rule");
  mo.gridding.taper_fraction = taper;
  mo.gridding.nadir_fill = nadir_fill;
  mo.apply_layback = layback;
  mo.altitude_source = parse_altitude_source(altitude_source, "altitude_source");
  mo.gain_normalisation = parse_gain_normalisation(gain_normalisation, "gain_normalisation");
  mo.max_pixels = max_pixels;
  if (bathymetry) q.bathymetry = *bathymetry;
  q.bathymetry_depth_positive = depth_positive;
  MosaicWriteOptions& wo = q.write;
  wo.format = parse_mosaic_raster_format(format, "format");
  wo.count_band = count;
  wo.overwrite = overwrite;
  wo.creation_options.assign(creation_options.begin(), creation_options.end());
  if (rgb) wo.rgb_path = rgb_path ? rgb_path->string() : default_rgb_path(output.string());
  wo.colormap = grey ? Colormap::grey : Colormap::black_brown_yellow;
  if (linear && !(*linear > 0.0)) {
    throw InputError("linear = " + std::to_string(*linear) + ". Violated constraint: linear > 0");
  }
  wo.linear_full_scale = linear.value_or(0.0);
  MosaicSummary s;
  {
    py::gil_scoped_release release;
    s = mosaic_files(q);
  }
  const XtfMosaicResult& r = s.result;
  py::dict d;
  py::list files;
  files.append(s.output.string());
  if (!s.rgb_path.empty()) files.append(s.rgb_path.string());
  d["files"] = files;
  d["text"] = s.text();
  d["warnings"] = s.warnings;
  d["cols"] = r.image.geometry.cols;
  d["rows"] = r.image.geometry.rows;
  d["epsg"] = r.frame.epsg();
  d["pixel_size_m"] = s.pixel_size_m;
  d["files_read"] = r.files;
  d["pings"] = r.pings;
  d["pings_gridded"] = r.pings_gridded;
  d["pings_no_navigation"] = r.pings_no_navigation;
  d["pings_no_samples"] = r.pings_no_samples;
  d["pings_no_altitude"] = r.pings_no_altitude;
  d["pings_dropped"] = r.pings_dropped;
  d["pings_header_altitude"] = r.pings_header_altitude;
  d["pings_tracked_altitude"] = r.pings_tracked_altitude;
  d["samples_placed"] = r.samples_placed;
  d["fill_points"] = r.fill_points;
  d["reader_anomalies"] = r.reader_anomalies;
  d["skipped_files"] = r.skipped_files;
  return d;
}

}  // namespace

void bind_products(py::module_& m) {
  m.def("mosaic", &mosaic, py::arg("inputs"), py::arg("output"), py::kw_only(),
        py::arg("pixel_size_m") = kDefaultMosaicPixelM, py::arg("rule") = "mean",
        py::arg("taper") = MosaicOptions{}.taper_fraction, py::arg("bathymetry") = py::none(),
        py::arg("depth_positive") = false, py::arg("layback") = false,
        py::arg("altitude_source") = "auto", py::arg("nadir_fill") = true,
        py::arg("gain_normalisation") = "off",
        py::arg("max_pixels") = XtfMosaicOptions{}.max_pixels, py::arg("count") = false,
        py::arg("format") = "COG",
        py::arg("creation_options") = std::map<std::string, std::string>{},
        py::arg("rgb_path") = py::none(), py::arg("rgb") = true, py::arg("grey") = false,
        py::arg("linear") = py::none(), py::arg("overwrite") = false,
        "What `sonarsynth mosaic INPUTS... -o OUTPUT` does, from the same library call: grids "
        "the sonar files (any listed format) into a float32 GeoTIFF and writes its display copy "
        "(rgb_path, default OUTPUT_rgb.tif; rgb=False: none). The options are the CLI's: "
        "pixel_size_m (--res), rule ('mean', 'max', 'nearest'), taper, bathymetry, "
        "depth_positive, layback, altitude_source ('auto', 'header', 'track'), nadir_fill "
        "(False: --no-nadir-fill), gain_normalisation ('off', 'range', 'angle'), max_pixels, "
        "count, format ('COG' or 'GTiff', --of), creation_options (dict, --co), grey, linear "
        "(display full scale), overwrite. Returns a dict: files, text (the line the CLI "
        "prints), warnings (what the CLI prints to stderr), cols, rows, epsg, pixel_size_m, "
        "files_read, pings, pings_gridded, pings_no_navigation, pings_no_samples, "
        "pings_no_altitude, pings_dropped, pings_header_altitude, pings_tracked_altitude, "
        "samples_placed, fill_points, reader_anomalies, skipped_files. Raises ValueError for "
        "bad options or paths, FormatError when no ping could be gridded or a file cannot be "
        "read.");
}

}  // namespace sonarsynth::python
