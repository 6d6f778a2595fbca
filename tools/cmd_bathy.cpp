// SPDX-License-Identifier: MIT
// `sonarsynth bathy`: generated bathymetry written as a GeoTIFF.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "sonarsynth/bathy_gen.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/bathy_spec_parser.hpp"
#include "sonarsynth/formats/raster/gdal_grid.hpp"
#include "sonarsynth/formats/raster/gdal_util.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::cli {
namespace {

const char* const kUsage =
    "usage: sonarsynth bathy -o OUT.tif --lat DEG --lon DEG --size WxH --cell M [options]\n\n"
    "Generates bathymetry (elevations, up positive: z = -depth + components) on a north-up grid\n"
    "centred on --lat/--lon, in the WGS 84 UTM/UPS zone of that point, and writes it as a\n"
    "float32 GeoTIFF. Positions X,Y are metres east/north of the grid centre along the grid axes;\n"
    "azimuths are degrees clockwise from grid north (as in a scene file's bathymetry.generate,\n"
    "which takes the same generators and bounds: docs/scene-format.md). Components can be\n"
    "repeated and are summed. The same options and --seed give the same file.";

// Parses "a,b,c" into min_count..max_count finite numbers; throws InputError naming the option.
std::vector<double> parse_numbers(const std::string& option, const std::string& value,
                                  std::size_t min_count, std::size_t max_count, const char* syntax,
                                  char separator = ',') {
  std::vector<double> out;
  std::size_t start = 0;
  auto bad = [&] {
    throw InputError("--" + option + " = '" + value + "'. Violated constraint: " + syntax);
  };
  while (true) {
    const std::size_t end = value.find(separator, start);
    const std::string item =
        value.substr(start, end == std::string::npos ? std::string::npos : end - start);
    char* stop = nullptr;
    const double v = std::strtod(item.c_str(), &stop);
    if (item.empty() || stop != item.c_str() + item.size() || !std::isfinite(v)) bad();
    out.push_back(v);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  if (out.size() < min_count || out.size() > max_count) bad();
  return out;
}

}  // namespace

int run_bathy(const std::vector<std::string>& args) {
  po::options_description opts("options");
  std::string output, size;
  double lat_deg = 0, lon_deg = 0, cell_m = 0, depth_m = BathyGenSpec{}.depth_m;
  std::string seed_text = "0";
  long long threads = 0;
  std::vector<std::string> slopes, ripples, fbms, seamounts, scarps, co;
  // clang-format off
  opts.add_options()
    ("output,o", po::value(&output)->required(), "output GeoTIFF")
    ("lat", po::value(&lat_deg)->required(), "latitude of the grid centre, degrees [-90, 90]")
    ("lon", po::value(&lon_deg)->required(), "longitude of the grid centre, degrees [-180, 360]")
    ("size", po::value(&size)->required(), "grid extent WxH, metres east x north, e.g. 200x100")
    ("cell", po::value(&cell_m)->required(), "cell size, metres, > 0")
    ("depth", po::value(&depth_m)->default_value(depth_m), "base water depth, metres, (0, 12000]")
    ("slope", po::value(&slopes)->composing(),
     "plane: DEG[,AZ] dip in degrees [0, 89] towards grid azimuth AZ (default 0 = north)")
    ("ripples", po::value(&ripples)->composing(),
     "sand ripples: WAVELENGTH,AMPLITUDE[,AZ[,ASYM]] metres, metres (crest to mean), crest "
     "azimuth (default 0), flank asymmetry [0, 1); a crest runs through the grid centre")
    ("fbm", po::value(&fbms)->composing(),
     "fractal roughness: RMS[,WAVELENGTH[,OCTAVES[,PERSISTENCE]]] metres, coarsest wavelength "
     "metres (default 20), octaves (default 6), amplitude ratio per octave (default 0.5)")
    ("seamount", po::value(&seamounts)->composing(),
     "Gaussian seamount: X,Y,HEIGHT,RADIUS metres (negative HEIGHT = pit, RADIUS = sigma)")
    ("scarp", po::value(&scarps)->composing(),
     "scarp: X,Y,AZ,HEIGHT[,WIDTH] a point on the scarp line, its strike azimuth, the step "
     "(right side higher by HEIGHT), width metres (default 2)")
    ("seed", po::value(&seed_text)->default_value("0"), "seed of the noise components")
    ("threads", po::value(&threads)->default_value(0), "worker threads (0 = all cores)")
    ("co", po::value(&co)->composing(), "GTiff creation option KEY=VALUE (repeatable)");
  // clang-format on
  add_overwrite_quiet_options(opts);
  po::variables_map vm;
  if (!parse(args, opts, {}, vm, kUsage)) return 0;

  const std::uint64_t seed = parse_uint64(seed_text, "seed");
  const std::vector<double> wh = parse_numbers("size", size, 2, 2, "WxH with W, H > 0", 'x');
  const bool overwrite = vm.count("overwrite") > 0;
  if (!overwrite && std::filesystem::exists(output)) {
    throw InputError("--output = " + output + ": already exists (use --overwrite to replace it)");
  }

  // The same declarations and builder as a scene file's bathymetry.generate.
  bathy_spec::GeneratorInput in;
  in.lat_deg = lat_deg;
  in.lon_deg = lon_deg;
  in.width_m = wh[0];
  in.height_m = wh[1];
  in.cell_m = cell_m;
  in.depth_m = depth_m;
  in.seed = seed;
  in.num_threads = checked_thread_count(threads, 0);
  std::vector<std::string> given;  // the option text of each component, for messages
  for (const bathy_spec::ComponentDecl& d : bathy_spec::components()) {
    const std::string option(d.cli_option);
    for (const std::string& text : vm.count(option) ? vm[option].as<std::vector<std::string>>()
                                                    : std::vector<std::string>{}) {
      const auto v = parse_numbers(option, text, d.cli_required, d.params.size(),
                                   (d.cli_syntax() + " numbers").c_str());
      bathy_spec::ComponentInput ci{&d, {v.begin(), v.end()}, std::nullopt};
      in.components.push_back(std::move(ci));
      given.push_back("--" + option + " = '" + text + "'");
    }
  }
  const auto fail = [&](std::optional<std::size_t> i, const bathy_spec::Param& p,
                        const std::string&) {
    std::ostringstream os;
    if (i) {
      os << given[*i] << ". Violated constraint: " << p.constraint(p.cli);
    } else {
      const double v = p.key == "lat_deg"   ? in.lat_deg
                       : p.key == "lon_deg" ? in.lon_deg
                       : p.key == "cell_m"  ? in.cell_m
                                            : in.depth_m;
      os << p.cli << " = " << v << ". Violated constraint: " << p.constraint(p.cli);
    }
    throw InputError(os.str());
  };
  const bathy_spec::Generated gen = bathy_spec::build(in, fail);
  const GeoFrame& frame = gen.frame;
  const BathyGenSpec& spec = gen.spec;

  GridWriteOptions wo;
  wo.overwrite = overwrite;
  wo.creation_options = parse_key_values(co, "co");
  gdal::validate_creation_options("GTiff", wo.creation_options, "bathy");
  std::string command = "sonarsynth bathy";
  for (const std::string& a : args) command += " " + a;
  wo.metadata.push_back({"SONARSYNTH_COMMAND", command});
  wo.metadata.push_back({"SONARSYNTH_SEED", std::to_string(seed)});

  const HeightGrid grid = generate_bathymetry(spec);
  write_height_grid_geotiff(output, frame, grid, wo);
  if (!vm.count("quiet")) {
    const auto [lo, hi] = grid.height_range();
    std::cout << "wrote " << output << ": " << spec.geometry.cols << " x " << spec.geometry.rows
              << " nodes of " << cell_m << " m, EPSG:" << frame.epsg() << ", heights " << lo
              << " .. " << hi << " m\n";
  }
  return 0;
}

}  // namespace sonarsynth::cli
