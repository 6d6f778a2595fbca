// SPDX-License-Identifier: MIT
// The bathymetry generators as both `sonarsynth bathy` and scene files
// (`bathymetry.generate`, and `bathymetry.components` on a file's grid) read them: one declaration
// per parameter (scene-file key, name on the command line, bounds), one builder.
// docs/scene-format.md, section `bathymetry`.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sonarsynth/bathy_gen.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::bathy_spec {

/// One number of a generator, in file units (metres, degrees).
struct Param {
  std::string_view key;  ///< scene-file key, e.g. "wavelength_m"
  std::string_view cli;  ///< its name in the command line's comma list, e.g. "WAVELENGTH"
  double lo;             ///< lower bound (-inf: none)
  double hi;             ///< upper bound (+inf: none)
  bool lo_open = false;  ///< lo < v rather than lo <= v
  bool hi_open = false;  ///< v < hi rather than v <= hi
  bool integer = false;
  /// "asymmetry >= 0 and < 1" (a finite number, always).
  std::string constraint(std::string_view name) const;
  bool accepts(double v) const;
};

/// One component type: its parameters in command-line order.
struct ComponentDecl {
  std::string_view type;        ///< scene-file `type`, e.g. "plane"
  std::string_view cli_option;  ///< `sonarsynth bathy` option, e.g. "slope"
  std::vector<Param> params;
  std::size_t cli_required;        ///< leading parameters the command line must give
  std::string cli_syntax() const;  ///< "DEG[,AZ]"
};

/// plane, ripples, fbm, seamount, scarp.
const std::vector<ComponentDecl>& components();
/// nullptr if `type` is not a component type.
const ComponentDecl* find_component(std::string_view type);
/// "one of plane, ripples, fbm, seamount, scarp".
std::string component_types_constraint();

/// The grid-level depth_m.
const Param& depth_param();

/// One component as read: values by parameter index (nullopt: not given, the generator
/// struct's default), and for fbm and ripples an optional seed offset.
struct ComponentInput {
  const ComponentDecl* decl = nullptr;
  std::vector<std::optional<double>> values;
  std::optional<std::uint64_t> seed_offset;
};

/// Everything the generator needs, in file units.
struct GeneratorInput {
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  double width_m = 0.0;
  double height_m = 0.0;
  double cell_m = 0.0;
  double depth_m = BathyGenSpec{}.depth_m;
  std::uint64_t seed = 0;
  unsigned num_threads = 0;
  std::vector<ComponentInput> components;
};

/// Reports a value that violates its parameter's bounds: `component` is the index into
/// GeneratorInput::components (std::nullopt for a grid-level number), `param` the declaration
/// whose bounds it violates, `constraint` those bounds as a scene file names them. Must throw.
using Reporter = std::function<void(std::optional<std::size_t> component, const Param& param,
                                    const std::string& constraint)>;

struct Generated {
  GeoFrame frame;
  BathyGenSpec spec;
};

/// The components as the generator takes them, every number checked against its declaration
/// (through `fail`): positions are metres from `centre` (local frame) along the grid axes,
/// azimuths clockwise from grid north, the plane's and the ripples' reference point is `centre`,
/// the n-th fbm layer's (and the n-th ripple field's) seed offset defaults to n.
std::vector<bathy::Component> build_components(const std::vector<ComponentInput>& inputs,
                                               const Eigen::Vector2d& centre, const Reporter& fail);

/// Checks every number against its declaration (through `fail`) and builds the frame (the
/// UTM/UPS zone of the centre) and the spec: positions are metres from the grid centre along the
/// grid axes, azimuths clockwise from grid north, the plane's and the ripples' reference point
/// is the grid centre, the n-th fbm layer's seed offset defaults to n. Grid-size errors of
/// BathyGenSpec::centred_geometry propagate as InputError.
Generated build(const GeneratorInput& in, const Reporter& fail);

}  // namespace sonarsynth::bathy_spec
