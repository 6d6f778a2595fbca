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
#include "sonarsynth/formats/gdal_grid.hpp"
#include "sonarsynth/formats/gdal_util.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::cli {
namespace {

const char* const kUsage =
    "usage: sonarsynth bathy -o OUT.tif --lat DEG --lon DEG --size WxH --cell M [options]\n\n"
    "Generates bathymetry (elevations, up positive: z = -depth + components) on a north-up grid\n"
    "centred on --lat/--lon, in the WGS 84 UTM/UPS zone of that point, and writes it as a\n"
    "float32 GeoTIFF. Positions X,Y are metres east/north of the grid centre; azimuths are\n"
    "degrees clockwise from true north at the centre. Components can be repeated and are summed.\n"
    "The same options and --seed give the same file.";

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

void require(bool ok, const std::string& option, double value, const std::string& constraint) {
  if (!ok) {
    std::ostringstream os;
    os << "--" << option << " = " << value << ". Violated constraint: " << constraint;
    throw InputError(os.str());
  }
}

}  // namespace

int run_bathy(const std::vector<std::string>& args) {
  po::options_description opts("options");
  std::string output, size;
  double lat_deg = 0, lon_deg = 0, cell_m = 0, depth_m = 20.0;
  std::string seed_text = "0";
  long long threads = 0;
  std::vector<std::string> slopes, ripples, fbms, seamounts, scarps, co;
  // clang-format off
  opts.add_options()
    ("output,o", po::value(&output)->required(), "output GeoTIFF")
    ("lat", po::value(&lat_deg)->required(), "latitude of the grid centre, degrees [-90, 90]")
    ("lon", po::value(&lon_deg)->required(), "longitude of the grid centre, degrees [-180, 180]")
    ("size", po::value(&size)->required(), "grid extent WxH, metres east x north, e.g. 200x100")
    ("cell", po::value(&cell_m)->required(), "cell size, metres, > 0")
    ("depth", po::value(&depth_m)->default_value(20.0), "base water depth, metres, > 0")
    ("slope", po::value(&slopes)->composing(),
     "plane: DEG[,AZ] dip in degrees [0, 90) towards azimuth AZ (default 0 = north)")
    ("ripples", po::value(&ripples)->composing(),
     "sand ripples: WAVELENGTH,AMPLITUDE[,AZ[,ASYM]] metres, metres (crest to mean), crest "
     "azimuth (default 0), flank asymmetry [0, 1)")
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
    ("co", po::value(&co)->composing(), "GTiff creation option KEY=VALUE (repeatable)")
    ("overwrite", "replace an existing output file")
    ("quiet,q", "print nothing on success");
  // clang-format on
  po::variables_map vm;
  if (!parse(args, opts, {}, vm, kUsage)) return 0;

  const std::uint64_t seed = parse_uint64(seed_text, "seed");
  require(std::abs(lat_deg) <= 90.0, "lat", lat_deg, "-90 <= --lat <= 90");
  require(std::abs(lon_deg) <= 180.0, "lon", lon_deg, "-180 <= --lon <= 180");
  require(cell_m > 0.0, "cell", cell_m, "--cell > 0");
  require(depth_m > 0.0, "depth", depth_m, "--depth > 0");
  const std::vector<double> wh = parse_numbers("size", size, 2, 2, "WxH with W, H > 0", 'x');
  require(wh[0] > 0.0 && wh[1] > 0.0, "size", wh[0] > 0.0 ? wh[1] : wh[0], "W > 0 and H > 0");
  require(wh[0] / cell_m >= 2.0 && wh[1] / cell_m >= 2.0, "cell", cell_m,
          "--cell <= half of the smaller --size side (at least 2 x 2 cells)");
  require(wh[0] / cell_m <= 1e6 && wh[1] / cell_m <= 1e6, "cell", cell_m,
          "at most 10^6 cells per side");
  const bool overwrite = vm.count("overwrite") > 0;
  if (!overwrite && std::filesystem::exists(output)) {
    throw InputError("--output = " + output + ": already exists (use --overwrite to replace it)");
  }

  const Geodetic centre{rad_from_deg(lat_deg), rad_from_deg(lon_deg), 0.0};
  const GeoFrame frame = GeoFrame::around(centre);
  const Eigen::Vector2d c = frame.local_from_geodetic(centre);
  // Azimuths on the command line are true; the generator works in grid azimuths.
  auto grid_az = [&](double true_deg) {
    return frame.grid_azimuth_from_true_rad(rad_from_deg(true_deg), c);
  };

  BathyGenSpec spec;
  spec.depth_m = depth_m;
  spec.seed = seed;
  spec.num_threads = checked_thread_count(threads, 0);
  spec.geometry = BathyGenSpec::centred_geometry(c.x(), c.y(), wh[0], wh[1], cell_m);
  for (const std::string& s : slopes) {
    const auto v = parse_numbers("slope", s, 1, 2, "DEG[,AZ] numbers");
    require(v[0] >= 0.0 && v[0] < 90.0, "slope", v[0], "0 <= DEG < 90");
    spec.components.push_back(bathy::Plane::from_dip(
        rad_from_deg(v[0]), grid_az(v.size() > 1 ? v[1] : 0.0), c.x(), c.y()));
  }
  for (const std::string& s : ripples) {
    const auto v = parse_numbers("ripples", s, 2, 4, "WAVELENGTH,AMPLITUDE[,AZ[,ASYM]] numbers");
    require(v[0] > 0.0, "ripples", v[0], "WAVELENGTH > 0");
    require(v[1] >= 0.0, "ripples", v[1], "AMPLITUDE >= 0");
    bathy::Ripples r;
    r.wavelength_m = v[0];
    r.amplitude_m = v[1];
    r.crest_azimuth_rad = grid_az(v.size() > 2 ? v[2] : 0.0);
    r.asymmetry = v.size() > 3 ? v[3] : 0.0;
    require(r.asymmetry >= 0.0 && r.asymmetry < 1.0, "ripples", r.asymmetry, "0 <= ASYM < 1");
    r.ref_x_m = c.x();
    r.ref_y_m = c.y();
    spec.components.push_back(r);
  }
  for (std::size_t i = 0; i < fbms.size(); ++i) {
    const auto v =
        parse_numbers("fbm", fbms[i], 1, 4, "RMS[,WAVELENGTH[,OCTAVES[,PERSISTENCE]]] numbers");
    bathy::Fbm f;
    f.rms_m = v[0];
    if (v.size() > 1) f.base_wavelength_m = v[1];
    if (v.size() > 2) {
      require(v[2] >= 1.0 && v[2] <= 24.0 && v[2] == std::floor(v[2]), "fbm", v[2],
              "OCTAVES an integer in [1, 24]");
      f.octaves = static_cast<int>(v[2]);
    }
    if (v.size() > 3) f.persistence = v[3];
    require(f.rms_m >= 0.0, "fbm", f.rms_m, "RMS >= 0");
    require(f.base_wavelength_m > 0.0, "fbm", f.base_wavelength_m, "WAVELENGTH > 0");
    require(f.persistence > 0.0 && f.persistence <= 1.0, "fbm", f.persistence,
            "0 < PERSISTENCE <= 1");
    f.seed_offset = i;
    spec.components.push_back(f);
  }
  for (const std::string& s : seamounts) {
    const auto v = parse_numbers("seamount", s, 4, 4, "X,Y,HEIGHT,RADIUS numbers");
    require(v[3] > 0.0, "seamount", v[3], "RADIUS > 0");
    spec.components.push_back(bathy::Seamount{c.x() + v[0], c.y() + v[1], v[2], v[3]});
  }
  for (const std::string& s : scarps) {
    const auto v = parse_numbers("scarp", s, 4, 5, "X,Y,AZ,HEIGHT[,WIDTH] numbers");
    const double width = v.size() > 4 ? v[4] : 2.0;
    require(width > 0.0, "scarp", width, "WIDTH > 0");
    spec.components.push_back(bathy::Scarp{c.x() + v[0], c.y() + v[1], grid_az(v[2]), v[3], width});
  }

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
