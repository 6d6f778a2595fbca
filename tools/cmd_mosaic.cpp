// SPDX-License-Identifier: MIT
// `sonarsynth mosaic`: sonar files of any listed format (ours or any vendor's) gridded into a
// GeoTIFF mosaic.
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/products/mosaic_files.hpp"
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

}  // namespace

int run_mosaic(const std::vector<std::string>& args) {
  po::options_description opts("options");
  std::vector<std::string> inputs, co;
  std::string output, rule = "mean", bathymetry, format = "COG", rgb_path;
  std::string altitude_source = "auto", gain_normalisation = "off";
  double wo_linear = 0.0;
  MosaicRequest q;
  // clang-format off
  opts.add_options()
    ("input", po::value(&inputs)->composing(),
     ("sonar files: " + sonar_format_names() + " (positional; format from content)").c_str())
    ("output,o", po::value(&output)->required(), "output GeoTIFF")
    ("res", po::value(&q.options.pixel_size_m)->default_value(kDefaultMosaicPixelM), "pixel size, metres, > 0")
    ("rule", po::value(&rule)->default_value("mean"), "mean | max | nearest")
    ("taper", po::value(&q.options.gridding.taper_fraction)->default_value(0.1, "0.1"),
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
    ("max-pixels", po::value(&q.options.max_pixels)->default_value(q.options.max_pixels),
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
  XtfMosaicOptions& mo = q.options;
  mo.gridding.rule = parse_mosaic_rule(rule, "--rule");
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

  MosaicWriteOptions& wo = q.write;
  wo.format = parse_mosaic_raster_format(format, "--of");
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
  q.inputs.assign(inputs.begin(), inputs.end());
  q.output = output;
  q.bathymetry = bathymetry;
  q.bathymetry_depth_positive = vm.count("depth-positive") > 0;
  q.on_warning = [](const std::string& w) {
    std::cerr << "sonarsynth mosaic: warning: " << w << "\n";
  };
  const MosaicSummary s = mosaic_files(q);
  if (!vm.count("quiet")) std::cout << s.text() << "\n";
  return 0;
}

}  // namespace sonarsynth::cli
