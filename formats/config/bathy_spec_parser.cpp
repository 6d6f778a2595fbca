// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/config/bathy_spec_parser.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "sonarsynth/error.hpp"

namespace sonarsynth::bathy_spec {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Bounds in file units (docs/scene-format.md). Defaults are the generator structs' own
// (bathy_gen.hpp); a plane's slope and azimuth default to 0.
Param any(std::string_view key, std::string_view cli) {
  return {key, cli, -kInf, kInf};
}

const std::vector<ComponentDecl> kComponents = {
    {"plane", "slope", {{"slope_deg", "DEG", 0.0, 89.0}, any("downslope_azimuth_deg", "AZ")}, 1},
    {"ripples",
     "ripples",
     {{"wavelength_m", "WAVELENGTH", 0.0, 1e6, true},
      {"amplitude_m", "AMPLITUDE", 0.0, 1e3},
      any("crest_azimuth_deg", "AZ"),
      {"asymmetry", "ASYM", 0.0, 1.0, false, true},
      {"bandwidth", "BANDWIDTH", 0.0, 0.5},
      {"amplitude_variation", "VARIATION", 0.0, 1.0}},
     2},
    {"fbm",
     "fbm",
     {{"rms_m", "RMS", 0.0, 1e3},
      {"wavelength_m", "WAVELENGTH", 0.0, 1e6, true},
      {"octaves", "OCTAVES", 1.0, 24.0, false, false, true},
      {"persistence", "PERSISTENCE", 0.0, 1.0, true}},
     1},
    {"seamount",
     "seamount",
     {any("east_m", "X"),
      any("north_m", "Y"),
      any("height_m", "HEIGHT"),
      {"radius_m", "RADIUS", 0.0, 1e6, true}},
     4},
    {"scarp",
     "scarp",
     {any("east_m", "X"),
      any("north_m", "Y"),
      any("azimuth_deg", "AZ"),
      any("height_m", "HEIGHT"),
      {"width_m", "WIDTH", 0.0, 1e6, true}},
     4},
};

const Param kLat{"lat_deg", "--lat", -90.0, 90.0};
const Param kLon{"lon_deg", "--lon", -180.0, 360.0};
const Param kCell{"cell_m", "--cell", 0.0, 1e5, true};
const Param kDepth{"depth_m", "--depth", 0.0, 12000.0, true};

}  // namespace

std::string Param::constraint(std::string_view name) const {
  std::ostringstream c;
  c << name;
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo) c << (lo_open ? " > " : " >= ") << lo;
  if (has_hi) c << (has_lo ? " and" : "") << (hi_open ? " < " : " <= ") << hi;
  if (integer) c << (has_lo || has_hi ? ", " : " ") << "an integer";
  if (!has_lo && !has_hi && !integer) c << " a finite number";
  return c.str();
}

bool Param::accepts(double v) const {
  if (!std::isfinite(v)) return false;
  if (lo_open ? !(v > lo) : !(v >= lo)) return false;
  if (hi_open ? !(v < hi) : !(v <= hi)) return false;
  return !integer || v == std::floor(v);
}

std::string ComponentDecl::cli_syntax() const {
  std::string s;
  for (std::size_t i = 0; i < params.size(); ++i) {
    if (i > 0) s += i >= cli_required ? "[," : ",";
    s += params[i].cli;
  }
  for (std::size_t i = std::max<std::size_t>(cli_required, 1); i < params.size(); ++i) s += "]";
  return s;
}

const std::vector<ComponentDecl>& components() {
  return kComponents;
}

const ComponentDecl* find_component(std::string_view type) {
  for (const ComponentDecl& d : kComponents) {
    if (d.type == type) return &d;
  }
  return nullptr;
}

std::string component_types_constraint() {
  std::string s = "one of";
  for (std::size_t i = 0; i < kComponents.size(); ++i) {
    s += (i ? ", " : " ") + std::string(kComponents[i].type);
  }
  return s;
}

const Param& depth_param() {
  return kDepth;
}

namespace {

// `fail` then an InputError, as a Reporter must throw.
void check(const Reporter& fail, std::optional<std::size_t> comp, const Param& p, double v) {
  if (!p.accepts(v)) {
    fail(comp, p, p.constraint(p.key));
    throw InputError("bathymetry generator: " + std::string(p.key) + ": " +
                     p.constraint(p.key));  // `fail` must throw; never reached otherwise
  }
}

}  // namespace

std::vector<bathy::Component> build_components(const std::vector<ComponentInput>& inputs,
                                               const Eigen::Vector2d& c, const Reporter& fail) {
  std::vector<bathy::Component> out;
  std::uint64_t fbm_index = 0;
  std::uint64_t ripples_index = 0;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const ComponentInput& ci = inputs[i];
    const ComponentDecl& d = *ci.decl;
    // value(k, fallback): the k-th parameter if given (checked), else the struct's default.
    auto value = [&](std::size_t k, double fallback) {
      const std::optional<double>& v = k < ci.values.size() ? ci.values[k] : std::nullopt;
      if (!v) return fallback;
      check(fail, i, d.params[k], *v);
      return *v;
    };
    // Azimuths in the file are degrees clockwise from grid north, the generator's own.
    if (d.type == "plane") {
      out.push_back(bathy::Plane::from_dip(rad_from_deg(value(0, 0.0)), rad_from_deg(value(1, 0.0)),
                                           c.x(), c.y()));
    } else if (d.type == "ripples") {
      bathy::Ripples r;
      r.wavelength_m = value(0, r.wavelength_m);
      r.amplitude_m = value(1, r.amplitude_m);
      r.crest_azimuth_rad = rad_from_deg(value(2, deg_from_rad(r.crest_azimuth_rad)));
      r.asymmetry = value(3, r.asymmetry);
      r.bandwidth = value(4, r.bandwidth);
      r.amplitude_variation = value(5, r.amplitude_variation);
      r.seed_offset = ci.seed_offset.value_or(ripples_index);
      ++ripples_index;
      r.ref_x_m = c.x();  // a crest through the grid centre
      r.ref_y_m = c.y();
      out.push_back(r);
    } else if (d.type == "fbm") {
      bathy::Fbm f;
      f.rms_m = value(0, f.rms_m);
      f.base_wavelength_m = value(1, f.base_wavelength_m);
      f.octaves = static_cast<int>(value(2, f.octaves));
      f.persistence = value(3, f.persistence);
      f.seed_offset = ci.seed_offset.value_or(fbm_index);
      ++fbm_index;
      out.push_back(f);
    } else if (d.type == "seamount") {
      bathy::Seamount s;
      s.centre_x_m = c.x() + value(0, s.centre_x_m);
      s.centre_y_m = c.y() + value(1, s.centre_y_m);
      s.height_m = value(2, s.height_m);
      s.radius_m = value(3, s.radius_m);
      out.push_back(s);
    } else if (d.type == "scarp") {
      bathy::Scarp s;
      s.x_m = c.x() + value(0, s.x_m);
      s.y_m = c.y() + value(1, s.y_m);
      s.azimuth_rad = rad_from_deg(value(2, deg_from_rad(s.azimuth_rad)));
      s.height_m = value(3, s.height_m);
      s.width_m = value(4, s.width_m);
      out.push_back(s);
    }
  }
  return out;
}

Generated build(const GeneratorInput& in, const Reporter& fail) {
  check(fail, std::nullopt, kLat, in.lat_deg);
  check(fail, std::nullopt, kLon, in.lon_deg);
  check(fail, std::nullopt, kCell, in.cell_m);
  check(fail, std::nullopt, kDepth, in.depth_m);

  const Geodetic centre{rad_from_deg(in.lat_deg), rad_from_deg(in.lon_deg), 0.0};
  Generated g{GeoFrame::around(centre), {}};
  const Eigen::Vector2d c = g.frame.local_from_geodetic(centre);
  BathyGenSpec& spec = g.spec;
  spec.geometry = BathyGenSpec::centred_geometry(c.x(), c.y(), in.width_m, in.height_m, in.cell_m);
  spec.depth_m = in.depth_m;
  spec.seed = in.seed;
  spec.num_threads = in.num_threads;
  spec.components = build_components(in.components, c, fail);
  return g;
}

}  // namespace sonarsynth::bathy_spec
