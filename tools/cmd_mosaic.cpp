// SPDX-License-Identifier: MIT
// `sonarsynth mosaic`: sonar files of any listed format (ours or any vendor's) gridded into a
// GeoTIFF mosaic.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "commands.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/products/mosaic_writer.hpp"
#include "sonarsynth/formats/products/xtf_mosaic.hpp"
#include "sonarsynth/formats/raster/gdal_grid.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"

namespace sonarsynth::cli {
namespace {

const char* const kUsage =
    "usage: sonarsynth mosaic FILES... -o MOSAIC.tif [options]\n\n"
    "Georeferences every sample of the sonar files (any format of the format list, read by\n"
    "content: sonarsynth info --help names them; sensor position, fish heading converted to grid\n"
    "north, pitch; slant->ground on a flat bottom from the altitude, or against --bathymetry) and\n"
    "grids the sample values linearly into a float32 GeoTIFF (NaN nodata, AREA_OR_POINT=Area) in\n"
    "the WGS 84 UTM/UPS zone of the data, Cloud-Optimized by default, plus an 8-bit RGBA display\n"
    "copy MOSAIC_rgb.tif with the black-brown-yellow colormap. Pings without navigation are\n"
    "skipped and counted; navigation outliers (a position jump of a few pings, a non-finite\n"
    "heading, a slant range over 10 x the file's median) are dropped and reported.\n"
    "Rules: mean = weighted mean with a sin^2 taper over the nearest and farthest 10% of the\n"
    "swath (nadir and far edge yield to mid-swath samples); max = strongest sample\n"
    "(shine-through); nearest = sample nearest to nadir.";

MosaicRule parse_rule(const std::string& s) {
  if (s == "mean") return MosaicRule::weighted_mean;
  if (s == "max") return MosaicRule::max;
  if (s == "nearest") return MosaicRule::nearest;
  throw InputError("--rule = '" + s + "'. Violated constraint: one of mean, max, nearest");
}

}  // namespace

int run_mosaic(const std::vector<std::string>& args) {
  po::options_description opts("options");
  std::vector<std::string> inputs, co;
  std::string output, rule = "mean", bathymetry, format = "COG", rgb_path;
  std::string altitude_source = "auto", gain_normalisation = "off";
  double wo_linear = 0.0;
  XtfMosaicOptions mo;
  // clang-format off
  opts.add_options()
    ("input", po::value(&inputs)->composing(),
     ("sonar files: " + sonar_format_names() + " (positional; format from content)").c_str())
    ("output,o", po::value(&output)->required(), "output GeoTIFF")
    ("res", po::value(&mo.pixel_size_m)->default_value(0.25), "pixel size, metres, > 0")
    ("rule", po::value(&rule)->default_value("mean"), "mean | max | nearest")
    ("taper", po::value(&mo.gridding.taper_fraction)->default_value(0.1, "0.1"),
     "mean: fraction of the swath tapered at nadir and at the far edge, [0, 0.5]")
    ("bathymetry", po::value(&bathymetry),
     "slant->ground against this elevation grid (any GDAL raster; its UTM zone is used)")
    ("depth-positive", "--bathymetry stores depths (positive down)")
    ("layback", "SensorX/Y is the tow point: place the fish Layback metres behind it")
    ("altitude-source", po::value(&altitude_source)->default_value("auto"),
     "auto | header | track: altitude for slant->ground; auto = the header's unless missing, "
     "<= 0 or disagreeing with the bottom tracked from the first return (docs/conversion.md)")
    ("no-bottom-pick", "same as --altitude-source header")
    ("no-nadir-fill", "leave nodata between nadir and the first seabed sample (docs/conversion.md)")
    ("gain-normalisation", po::value(&gain_normalisation)->default_value("off"),
     "off | range | angle: empirical across-track gain over all the files, by slant range or "
     "depression angle (docs/conversion.md)")
    ("max-pixels", po::value(&mo.max_pixels)->default_value(mo.max_pixels),
     "refuse a mosaic of more pixels than this (about 20 bytes each while gridding)")
    ("count", "add band 2: number of contributions per pixel")
    ("of", po::value(&format)->default_value("COG"), "COG | GTiff")
    ("co", po::value(&co)->composing(), "creation option KEY=VALUE (repeatable)")
    ("rgb", po::value(&rgb_path), "display copy path (default MOSAIC_rgb.tif; .png allowed)")
    ("no-rgb", "do not write the display copy")
    ("grey", "display copy in grey instead of black-brown-yellow")
    ("linear", po::value(&wo_linear),
     "display copy: value / VALUE linearly instead of a dB window (e.g. 32767, the full scale "
     "of sonarsynth's u16 samples: the founding paper's grey level)")
    ("overwrite", "replace existing output files")
    ("quiet,q", "print nothing on success (warnings still go to stderr)");
  // clang-format on
  po::positional_options_description positional;
  positional.add("input", -1);
  po::variables_map vm;
  if (!parse(args, opts, positional, vm, kUsage)) return 0;
  if (inputs.empty())
    throw InputError("no input file. Violated constraint: at least one sonar file");
  mo.gridding.rule = parse_rule(rule);
  mo.apply_layback = vm.count("layback") > 0;
  mo.gridding.nadir_fill = vm.count("no-nadir-fill") == 0;
  mo.altitude_source = parse_altitude_source(altitude_source, "--altitude-source");
  if (vm.count("no-bottom-pick")) {
    if (!vm["altitude-source"].defaulted() && mo.altitude_source != AltitudeSource::kHeader) {
      throw InputError("--no-bottom-pick and --altitude-source " + altitude_source +
                       ". Violated constraint: --no-bottom-pick means --altitude-source header");
    }
    mo.altitude_source = AltitudeSource::kHeader;
  }
  mo.gain_normalisation = parse_gain_normalisation(gain_normalisation, "--gain-normalisation");
  mo.validate();

  MosaicWriteOptions wo;
  if (format == "COG" || format == "cog") {
    wo.format = MosaicRasterFormat::cog;
  } else if (format == "GTiff" || format == "gtiff") {
    wo.format = MosaicRasterFormat::gtiff;
  } else {
    throw InputError("--of = '" + format + "'. Violated constraint: COG or GTiff");
  }
  wo.count_band = vm.count("count") > 0;
  wo.overwrite = vm.count("overwrite") > 0;
  wo.creation_options = parse_key_values(co, "co");
  if (vm.count("no-rgb") == 0) wo.rgb_path = rgb_path.empty() ? default_rgb_path(output) : rgb_path;
  wo.colormap = vm.count("grey") ? Colormap::grey : Colormap::black_brown_yellow;
  if (vm.count("linear") && !(wo_linear > 0.0)) {
    throw InputError("--linear = " + std::to_string(wo_linear) +
                     ". Violated constraint: --linear > 0");
  }
  wo.linear_full_scale = vm.count("linear") ? wo_linear : 0.0;
  std::string command = "sonarsynth mosaic";
  for (const std::string& a : args) command += " " + a;
  wo.metadata.push_back({"SONARSYNTH_COMMAND", command});
  wo.metadata.push_back({"SONARSYNTH_MOSAIC_RULE", rule});
  wo.metadata.push_back({"SONARSYNTH_ALTITUDE_SOURCE", to_string(mo.altitude_source)});
  wo.metadata.push_back({"SONARSYNTH_GAIN_NORMALISATION", to_string(mo.gain_normalisation)});
  // Refuse existing outputs (and inputs named as outputs) before the (long) gridding.
  refuse_equal_outputs({output, wo.rgb_path}, {"-o", "--rgb"});
  {
    std::vector<std::string> all_inputs = inputs;
    all_inputs.push_back(bathymetry);
    refuse_output_over_input({output, wo.rgb_path}, all_inputs);
  }
  wo.validate();  // display copy name, creation options: before the (long) gridding
  for (const std::string& p : {output, wo.rgb_path}) {
    if (!p.empty() && !wo.overwrite && std::filesystem::exists(p)) {
      throw InputError("output " + p + " already exists (use --overwrite to replace it)");
    }
  }

  std::optional<LoadedGrid> bathy;
  if (!bathymetry.empty()) {
    GridReadOptions ro;
    ro.depth_positive_down = vm.count("depth-positive") > 0;
    bathy = read_height_grid(bathymetry, ro);
  } else if (vm.count("depth-positive") > 0) {
    throw InputError(
        "--depth-positive given without --bathymetry. Violated constraint: "
        "--depth-positive describes the --bathymetry grid");
  }
  const std::vector<std::filesystem::path> files(inputs.begin(), inputs.end());
  const XtfMosaicResult r = mosaic_xtf(files, mo, bathy ? &*bathy : nullptr);
  for (const std::string& m : r.skipped_files) {
    std::cerr << "sonarsynth mosaic: warning: skipped " << m << "\n";
  }
  if (r.pings_gridded == 0 && bathy) {
    // With a bathymetry, a ping places nothing where its swath misses the grid: say so when the
    // grid and the survey do not overlap at all.
    const GridGeometry& m = r.image.geometry;
    const double half_x = 0.5 * m.dx_m, half_y = 0.5 * std::abs(m.dy_m);
    const double mx0 = m.x_of_col(0) - half_x;
    const double mx1 = m.x_of_col(static_cast<double>(m.cols) - 1.0) + half_x;
    const double my_a = m.y_of_row(0), my_b = m.y_of_row(static_cast<double>(m.rows) - 1.0);
    const double my0 = std::min(my_a, my_b) - half_y, my1 = std::max(my_a, my_b) + half_y;
    const Eigen::Vector4d bb = bathy->grid.bounds();
    if (bb[2] < mx0 || bb[0] > mx1 || bb[3] < my0 || bb[1] > my1) {
      const auto corner = [&](double x, double y) {
        const Eigen::Vector2d p = r.frame.projected_from_local({x, y});
        std::ostringstream os;
        os.setf(std::ios::fixed);
        os.precision(1);
        os << "(" << p.x() << ", " << p.y() << ")";
        return os.str();
      };
      throw InputError("--bathymetry " + bathymetry + ": the grid " + corner(bb[0], bb[1]) +
                       " .. " + corner(bb[2], bb[3]) + " does not overlap the survey " +
                       corner(mx0, my0) + " .. " + corner(mx1, my1) + " (EPSG:" +
                       std::to_string(r.frame.epsg()) + " metres): no ping could be gridded");
    }
  }
  if (r.pings_gridded == 0) {
    std::string names;
    for (const std::string& f : inputs) names += (names.empty() ? "" : ", ") + f;
    throw FormatError(names + ": no ping could be gridded (" + std::to_string(r.pings) +
                      " pings, " + std::to_string(r.pings_no_navigation) + " without navigation, " +
                      std::to_string(r.pings_no_altitude) + " without altitude)");
  }
  if (r.pings_dropped > 0) {
    std::cerr << "sonarsynth mosaic: warning: dropped " << r.pings_dropped << " of " << r.pings
              << " pings as navigation outliers (" << r.dropped_position_jump << " position jumps, "
              << r.dropped_slant_range << " slant ranges, " << r.dropped_heading << " headings):\n";
    for (const std::string& e : r.dropped_examples) std::cerr << "  " << e << "\n";
    if (r.dropped_examples.size() < r.pings_dropped) {
      std::cerr << "  ... (" << r.pings_dropped - r.dropped_examples.size() << " more)\n";
    }
  }
  warn_reader_anomalies("mosaic", r.reader_anomalies, r.reader_anomaly_messages);
  if (r.pings_no_navigation > 0) {
    std::cerr << "sonarsynth mosaic: warning: skipped " << r.pings_no_navigation << " of "
              << r.pings << " pings with missing or zero navigation\n";
  }
  if (r.pings_no_samples > 0) {
    std::cerr << "sonarsynth mosaic: warning: skipped " << r.pings_no_samples
              << " pings without port/starboard samples\n";
  }
  if (r.pings_no_altitude > 0) {
    std::cerr << "sonarsynth mosaic: warning: skipped " << r.pings_no_altitude
              << " pings without altitude\n";
  }
  if (r.pings_tracked_altitude > 0 && mo.altitude_source == AltitudeSource::kAuto) {
    std::cerr << "sonarsynth mosaic: warning: altitude of " << r.pings_tracked_altitude << " of "
              << r.pings_tracked_altitude + r.pings_header_altitude
              << " gridded pings tracked from the first bottom return (" << r.pings_header_disagreed
              << " where the header altitude disagreed, the others without one)\n";
  }
  try {
    write_mosaic(output, r.frame, r.image, wo);
  } catch (const std::system_error& e) {
    // The display copy is written on a thread of its own, alongside the mosaic.
    if (e.code() != std::errc::resource_unavailable_try_again || wo.rgb_path.empty()) throw;
    throw FormatError(output + ": could not start the thread that writes the display copy " +
                      wo.rgb_path + " (" + e.code().message() +
                      "; the limit on threads, ulimit -u, or on address space, ulimit -v, is "
                      "reached); nothing written (--no-rgb needs no thread)");
  }
  if (!vm.count("quiet")) {
    const GridGeometry& g = r.image.geometry;
    std::cout << "wrote " << output << ": " << g.cols << " x " << g.rows << " pixels of "
              << mo.pixel_size_m << " m, EPSG:" << r.frame.epsg() << ", " << r.pings_gridded
              << " of " << r.pings << " pings, " << r.samples_placed << " samples ("
              << r.fill_points << " fill points); altitude: " << r.pings_header_altitude
              << " header, " << r.pings_tracked_altitude << " tracked";
    if (!wo.rgb_path.empty()) std::cout << "; display copy " << wo.rgb_path;
    std::cout << "\n";
  }
  return 0;
}

}  // namespace sonarsynth::cli
