// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <variant>
#include <vector>

#include "sonarsynth/height_grid.hpp"

namespace sonarsynth {

/// Generated bathymetry: a base depth plus a sum of analytic and noise components, evaluated at
/// the nodes of a grid in the local frame (see GeoFrame). Every component is a function of the
/// local (x, y) position only, so the same spec gives the same heights for any grid that shares
/// nodes, any evaluation order and any thread count.
///
/// Azimuths are clockwise from grid north (+y) towards grid east (+x), radians.
namespace bathy {

/// A plane: z += slope_x * (x - ref_x_m) + slope_y * (y - ref_y_m).
struct Plane {
  double slope_x = 0.0;  ///< dz/dx, dimensionless (tan of the dip along x), finite
  double slope_y = 0.0;  ///< dz/dy, dimensionless, finite
  double ref_x_m = 0.0;  ///< local x where the plane adds 0, metres
  double ref_y_m = 0.0;  ///< local y where the plane adds 0, metres

  /// A plane dipping by `slope_rad` ([0, pi/2)) towards the grid azimuth `downslope_azimuth_rad`
  /// (the direction in which the seabed gets deeper).
  static Plane from_dip(double slope_rad, double downslope_azimuth_rad, double ref_x_m = 0.0,
                        double ref_y_m = 0.0);
};

/// Sand ripples. With bandwidth = 0 parallel crests, z += amplitude_m * cos(t + asymmetry * sin t),
/// where t = 2 pi (distance across the crests from the reference point) / wavelength_m.
/// asymmetry = 0 gives a sinusoid; 0 < asymmetry < 1 steepens one flank (lee side) while keeping
/// two zero crossings per wavelength.
///
/// With bandwidth > 0 (docs/physics.md §2.1 "Ripple fields"): a narrow-band random field around
/// the peak wavevector k0 n (k0 = 2 pi / wavelength_m, n across the crests),
///   w(x) = sum_j exp(i psi_j) exp(i (k0 n + q_j) . (x - ref)) / sqrt(kRippleModes),
/// with q_j ~ N(0, (bandwidth k0)^2 I) and psi_j uniform, seeded from (seed + seed_offset); then
/// z += amplitude_m |w|^v / sqrt(Gamma(1 + v)) cos(t + asymmetry sin t), t = arg w,
/// v = amplitude_variation. The wavelength and the crest azimuth wander over a distance of about
/// 1 / (bandwidth k0), crests end and fork where w = 0 (about 2 pi bandwidth^2 such defects per
/// wavelength squared), and the expected mean square height is amplitude_m^2 / 2 as for the
/// sinusoid. For v = 1 and asymmetry = 0 the expected power spectrum is a 2-D Gaussian of rms
/// width bandwidth k0 per axis about +-k0 n.
struct Ripples {
  double wavelength_m = 1.0;  ///< crest spacing (peak wavelength), metres, > 0
  double amplitude_m = 0.05;  ///< crest height above the mean (half the crest-to-trough), m, >= 0
  double crest_azimuth_rad = 0.0;  ///< direction along which the crests run, grid azimuth, radians
  double asymmetry = 0.0;          ///< flank asymmetry, [0, 1)
  double ref_x_m = 0.0;            ///< local x of a crest (bandwidth 0), metres
  double ref_y_m = 0.0;            ///< local y of a crest (bandwidth 0), metres
  /// Relative rms spectral width sigma_k / k0 per axis, [0, 0.5]; 0 = the pure sinusoid.
  double bandwidth = 0.1;
  /// Envelope exponent v, [0, 1]: 0 = every crest the same height (only the phase wanders),
  /// 1 = the Gaussian field's Rayleigh envelope (crests fade in and out).
  double amplitude_variation = 0.5;
  std::uint64_t seed_offset = 0;  ///< added to the spec's seed (decorrelates two ripple fields)
};

/// Number of plane waves of a ripple field with bandwidth > 0.
inline constexpr int kRippleModes = 96;

/// Fractal roughness: fractional Brownian motion, the sum over octaves k = 0..octaves-1 of
/// gradient (Perlin) noise of wavelength base_wavelength_m / 2^k and amplitude persistence^k,
/// scaled so that its expected rms over a large area is rms_m. The lattice gradients come from
/// splitmix64 of (seed + seed_offset, lattice x, lattice y, octave): deterministic and
/// independent of the evaluation order.
struct Fbm {
  double rms_m = 0.1;               ///< expected rms height, metres, >= 0
  double base_wavelength_m = 20.0;  ///< lattice spacing of the coarsest octave, metres, > 0
  int octaves = 6;                  ///< number of octaves, [1, 24]
  double persistence = 0.5;         ///< amplitude ratio between octaves, (0, 1]; 2^-H for Hurst H
  std::uint64_t seed_offset = 0;    ///< added to the spec's seed (decorrelates two Fbm layers)

  /// The component's height at local (x_m, y_m), metres, for the spec's `seed`: the sum over
  /// octaves k of amplitude_k gradient_noise at frequency 2^k / base_wavelength_m (the value
  /// generate_bathymetry adds at a node, evaluated anywhere).
  double height_m(double x_m, double y_m, std::uint64_t seed) const;
};

/// A Gaussian seamount (or pit, with a negative height): z += height_m exp(-r^2 / (2 radius^2)).
struct Seamount {
  double centre_x_m = 0.0;  ///< local x of the summit, metres
  double centre_y_m = 0.0;  ///< local y of the summit, metres
  double height_m = 5.0;    ///< summit height above the surrounding seabed, metres, finite
  double radius_m = 10.0;   ///< Gaussian standard deviation, metres, > 0
};

/// A straight scarp: z += 0.5 height_m tanh(2 d / width_m), d = signed distance from the line
/// through (x_m, y_m) with grid azimuth azimuth_rad, positive to the right of the azimuth. The
/// right side ends height_m above the left; 76 % of the step lies within |d| < width_m / 2.
struct Scarp {
  double x_m = 0.0;          ///< local x of a point on the scarp line, metres
  double y_m = 0.0;          ///< local y of a point on the scarp line, metres
  double azimuth_rad = 0.0;  ///< strike of the scarp line, grid azimuth, radians
  double height_m = 2.0;     ///< step height (right side minus left side), metres, finite
  double width_m = 2.0;      ///< step width, metres, > 0
};

using Component = std::variant<Plane, Ripples, Fbm, Seamount, Scarp>;

}  // namespace bathy

/// What to generate: heights z = -depth_m + sum of components at every node of `geometry`.
struct BathyGenSpec {
  double depth_m = 20.0;   ///< base water depth, metres, > 0 (heights are elevations: z = -depth)
  GridGeometry geometry;   ///< nodes in the local frame; >= 2 x 2 nodes
  std::uint64_t seed = 0;  ///< seed of every noise component
  std::vector<bathy::Component> components;  ///< summed in order
  unsigned num_threads = 0;  ///< worker threads, 0 = hardware concurrency; output is identical
  /// Largest generated grid: 2^28 nodes (1 GiB of float32 heights).
  static constexpr double kMaxCells = 268435456.0;

  /// Throws InputError naming the violated constraint.
  void validate() const;
  /// As validate(), without depth_m (add_bathymetry_components does not use it).
  void validate_components() const;

  /// cols x rows nodes of spacing cell_m covering width_m x height_m (node = cell centre, as
  /// GDAL's Area pixels), north-up, centred on (centre_x_m, centre_y_m).
  /// cols = round(width_m / cell_m); throws InputError unless cell_m > 0, the sizes are positive
  /// and the grid has 2 x 2 to 10^6 x 10^6 nodes and at most kMaxCells in all (checked before
  /// anything is allocated).
  static GridGeometry centred_geometry(double centre_x_m, double centre_y_m, double width_m,
                                       double height_m, double cell_m);
};

/// Evaluates the spec at every node (multi-threaded over rows); throws InputError via validate().
HeightGrid generate_bathymetry(const BathyGenSpec& spec);

/// Adds the spec's components (not depth_m) to every node of `grid`, in place:
/// z = z + float(sum of the components at the node), a float32 addition (a hole stays a hole).
/// The components alone are this on a grid of zeros. grid.geometry() must equal spec.geometry;
/// throws InputError via validate_components(). Multi-threaded as generate_bathymetry(), with
/// the same per-node values; no memory beyond a row per thread.
void add_bathymetry_components(const BathyGenSpec& spec, HeightGrid& grid);

/// Gradient noise in [-1, 1] (about), zero at integer lattice points, C2-continuous (quintic fade),
/// from hashed gradients: splitmix64 of (seed, floor(u), floor(v), octave).
double gradient_noise(double u, double v, std::uint64_t seed, std::uint64_t octave);

}  // namespace sonarsynth
