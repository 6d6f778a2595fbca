// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/config/scene_bathymetry.hpp"

#include <cmath>
#include <cstdio>
#include <optional>
#include <set>

#include "sonarsynth/bathy_gen.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/bathy_spec_parser.hpp"
#include "sonarsynth/formats/config/option_table.hpp"
#include "sonarsynth/formats/raster/gdal_grid.hpp"

namespace sonarsynth::scene_bathymetry {
namespace {

namespace fs = std::filesystem;
using yaml::Fields;

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// A generator component: its keys and bounds are those of formats/config/bathy_spec_parser.cpp,
// shared with `sonarsynth bathy`.
bathy_spec::ComponentInput read_component(const Fields& c) {
  const std::string type = c.text("type");
  bathy_spec::ComponentInput in;
  in.decl = bathy_spec::find_component(type);
  if (!in.decl) c.fail_value("type", bathy_spec::component_types_constraint());
  std::set<std::string> keys{"type"};
  for (const bathy_spec::Param& p : in.decl->params) {
    const std::string key(p.key);
    keys.insert(key);
    in.values.push_back(c.given(key) ? std::optional<double>(c.number(key)) : std::nullopt);
  }
  if (type == "fbm" || type == "ripples") {
    keys.insert("seed_offset");
    if (c.given("seed_offset")) in.seed_offset = c.seed("seed_offset", 0);
  }
  c.only(keys);
  return in;
}

// The components of `list` (a `components` sequence), checked; positions relative to `centre`.
std::vector<bathy::Component> read_components(const Fields& list_owner,
                                              const std::vector<Fields>& comps,
                                              const Eigen::Vector2d& centre) {
  std::vector<bathy_spec::ComponentInput> in;
  for (const Fields& comp : comps) in.push_back(read_component(comp));
  return bathy_spec::build_components(
      in, centre,
      [&](std::optional<std::size_t> i, const bathy_spec::Param& p, const std::string& constraint) {
        if (i) comps[*i].fail_value(std::string(p.key), constraint);
        list_owner.fail_value("components", constraint);
      });
}

// A file's grid defaults to bicubic: a surveyed DEM rendered bilinearly is a mosaic of facets
// whose slope jumps at every cell edge, and a sonar at a low grazing angle shows each as a step
// of brightness (docs/physics.md §2.1 "Seabed interpolation"). A generated grid, fine enough
// for its components, defaults to bilinear.
Interpolation read_interpolation(const Fields& b) {
  const std::string name = b.text("interpolation", b.has("file") ? "bicubic" : "bilinear");
  if (name == "bilinear") return Interpolation::kBilinear;
  if (name == "bicubic") return Interpolation::kBicubic;
  b.fail_value("interpolation", "interpolation one of bilinear, bicubic");
}

// limits.max_memory_gb of the document (its declared bounds), or the default.
double max_memory_gb(const Fields& top) {
  const options::Option& o = options::at("limits.max_memory_gb");
  if (!top.has("limits")) return RunLimits{}.max_memory_gb;
  const Fields lim = top.child("limits");
  const double v = lim.number(std::string(o.key), RunLimits{}.max_memory_gb);
  if (!o.accepts(v)) lim.fail_value(std::string(o.key), o.constraint());
  return v;
}

// bathymetry.resample_cell_m and bathymetry.components on a file's grid: the grid resampled
// (with its interpolation) onto nodes resample_cell_m apart over the same area, then the
// components added at every node (add_bathymetry_components). The finer grid is bilinear.
void refine(const Fields& top, const Fields& b, std::uint64_t seed, unsigned num_threads,
            HeightGrid& grid) {
  if (b.has("resample_cell_m")) {
    const GridGeometry& g = grid.geometry();
    const double file_cell = std::min(std::abs(g.dx_m), std::abs(g.dy_m));
    const double cell = b.number_in("resample_cell_m", 0.0, 0.0, 1e5, true);
    if (!(cell <= file_cell)) {
      b.fail_value("resample_cell_m", "resample_cell_m <= the file's cell (" + num(file_cell) +
                                          " m): the resampled grid is finer");
    }
    const GridGeometry fine = [&] {
      try {
        return refined_geometry(g, cell);
      } catch (const InputError& e) {
        b.fail("resample_cell_m", e.what());
      }
    }();
    // While resampling both grids are held (float32 heights).
    const double nodes = static_cast<double>(fine.cols) * static_cast<double>(fine.rows);
    const double bytes = 4.0 * (nodes + static_cast<double>(g.size()));
    const double limit_gb = max_memory_gb(top);
    if (!(bytes <= limit_gb * 1e9)) {
      b.fail("resample_cell_m",
             "resample_cell_m = " + num(cell) + " m turns the " + std::to_string(g.cols) + " x " +
                 std::to_string(g.rows) + " grid (cell " + num(std::abs(g.dx_m)) + " x " +
                 num(std::abs(g.dy_m)) + " m) into " + std::to_string(fine.cols) + " x " +
                 std::to_string(fine.rows) + " = " + num(nodes) + " nodes: " + num(bytes / 1e9) +
                 " GB of heights while resampling, more than " +
                 "limits.max_memory_gb = " + num(limit_gb) +
                 ". Violated constraint: 4 bytes x (resampled + file nodes) <= "
                 "limits.max_memory_gb; raise bathymetry.resample_cell_m or "
                 "limits.max_memory_gb");
    }
    grid = resample(grid, fine, num_threads);
  }
  const std::vector<Fields> comps = b.sequence("components");
  if (comps.empty()) return;
  const Eigen::Vector4d bb = grid.bounds();
  BathyGenSpec spec;
  spec.geometry = grid.geometry();
  spec.seed = seed;
  spec.num_threads = num_threads;
  spec.components = read_components(b, comps, {0.5 * (bb[0] + bb[2]), 0.5 * (bb[1] + bb[3])});
  try {
    add_bathymetry_components(spec, grid);
  } catch (const InputError& e) {
    b.fail("components", e.what());
  }
}

}  // namespace

Scene load(const Fields& top, const std::string& path, const fs::path& base_dir,
           const SceneLoadOptions& options) {
  const Fields b = top.child("bathymetry");
  b.only({"file", "depth_positive_down", "band", "generate", "interpolation", "resample_cell_m",
          "components", "seed"});
  if (b.has("file") == b.has("generate")) b.fail("", "give exactly one of file or generate");
  const Interpolation interpolation = read_interpolation(b);
  // A generated scene without its own seed takes --seed, else the file's top-level seed.
  const std::uint64_t default_seed = options.seed.value_or(top.seed("seed", 1));
  std::optional<Scene> built;
  if (b.has("file")) {
    GridReadOptions ro;
    ro.depth_positive_down = b.boolean("depth_positive_down", false);
    ro.band = static_cast<int>(b.integer("band", 1));
    LoadedGrid lg = [&] {
      try {
        return read_height_grid(yaml::resolve_path(base_dir, b.text("file")), ro);
      } catch (const InputError& e) {
        b.fail("", e.what());
      }
    }();
    built.emplace(lg.frame);
    built->bathymetry = std::move(lg.grid);
    built->bathymetry.set_interpolation(interpolation);
    refine(top, b, b.seed("seed", default_seed), options.num_threads, built->bathymetry);
  } else {
    for (const char* key : {"resample_cell_m", "components", "seed"}) {
      if (b.has(key)) {
        b.fail(key, std::string("applies to a file's grid; a generated one takes generate.") +
                        (std::string(key) == "resample_cell_m" ? "cell_m" : key));
      }
    }
    const Fields g = b.child("generate");
    g.only({"centre", "size_m", "cell_m", "depth_m", "seed", "components"});
    const Fields c = g.child("centre");
    c.only({"lat_deg", "lon_deg"});
    bathy_spec::GeneratorInput in;
    in.lat_deg = c.number("lat_deg");  // both required: a missing one is not taken as 0
    in.lon_deg = c.number("lon_deg");
    const auto size = g.numbers("size_m", 2);
    in.width_m = size[0];
    in.height_m = size[1];
    in.cell_m = g.number("cell_m", 0.0);
    in.depth_m = g.number("depth_m", in.depth_m);
    in.seed = g.seed("seed", default_seed);
    in.num_threads = options.num_threads;
    const std::vector<Fields> comps = g.sequence("components");
    for (const Fields& comp : comps) in.components.push_back(read_component(comp));
    const auto fail = [&](std::optional<std::size_t> i, const bathy_spec::Param& p,
                          const std::string& constraint) {
      const std::string key(p.key);
      const Fields& where = i ? comps[*i] : (key == "lat_deg" || key == "lon_deg" ? c : g);
      where.fail_value(key, constraint);
    };
    try {
      bathy_spec::Generated gen = bathy_spec::build(in, fail);
      built.emplace(gen.frame);
      built->bathymetry = generate_bathymetry(gen.spec);
    } catch (const InputError& e) {
      if (std::string(e.what()).rfind(path + ":", 0) == 0) throw;
      g.fail("", e.what());
    }
    built->bathymetry.set_interpolation(interpolation);
  }
  // The rule of the survey check (docs/scene-format.md, "Checks before the run"), for the whole
  // grid: a seabed with no node below sea level can carry no survey line.
  const auto [lo, hi] = built->bathymetry.height_range();
  if (const std::string problem = seabed_above_sea_level_problem(lo, hi); !problem.empty())
    b.fail("", problem + " (see bathymetry.depth_positive_down)");
  return std::move(*built);
}

}  // namespace sonarsynth::scene_bathymetry
