// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "sonarsynth/height_grid.hpp"

namespace sonarsynth {

/// A seabed or object material and its backscatter parameters.
struct Material {
  std::string name;
  /// Lambert coefficient mu (linear, dimensionless): sigma_b = mu sin^2(grazing). Range (0, 1].
  /// 10 log10(mu) is typically -35 dB (mud) ... -12 dB (rock); see docs/physics.md §1.5.
  double lambert_mu = 0.01;
  /// Reflectivity R of the founding paper's model I = R K Phi cos(theta), range [0, 1].
  double paper_reflectivity = 0.5;
  /// Shape nu of the K-distribution texture (Gamma(nu, 1/nu)); 0 = no texture (Rayleigh).
  double texture_shape_nu = 0.0;
  /// RMS height of the surface roughness of objects of this material, metres, >= 0; 0 = smooth
  /// (the default). Object section nodes move along their normal by a Gaussian-correlated field
  /// of this RMS (docs/physics.md §1.11). The seabed's roughness is its bathymetry's.
  double roughness_rms_m = 0.0;
  /// Correlation length L of that roughness, metres, > 0: autocorrelation exp(-d^2 / (2 L^2)).
  double roughness_length_m = 0.05;
  /// Kirchhoff (near-normal, specular) reflection coefficient rho of objects of this material,
  /// linear, [0, 1]; 0 = no glint (the default). Object facets then backscatter the Lambert term
  /// plus rho / (8 s^2 cos^4 theta) exp(-tan^2 theta / (2 s^2)), theta the incidence from the
  /// facet's normal (KirchhoffLobe, docs/physics.md §1.11). Not applied to the seabed (its
  /// near-normal return is the sensor stage's first return, §1.10).
  double specular_rho = 0.0;
  /// RMS slope s of the unresolved (sub-facet) roughness of that lobe, (0, 1].
  double specular_rms_slope = 0.1;

  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// Materials by index; index 0 .. size-1 are what maps and objects refer to.
class MaterialTable {
 public:
  /// The built-in classes: mud, sand, gravel, rock (seabeds) and steel, concrete (objects), with
  /// literature-midpoint values (docs/physics.md §1.5, +-5 dB site to site).
  static MaterialTable defaults();

  /// Adds or replaces a material by name; returns its index.
  std::uint16_t set(const Material& m);
  /// Index of a material by name; throws InputError("unknown material 'x' (known: ...)").
  std::uint16_t index_of(const std::string& name) const;
  bool contains(const std::string& name) const;
  const Material& operator[](std::uint16_t i) const { return materials_.at(i); }
  std::size_t size() const { return materials_.size(); }
  const std::vector<Material>& all() const { return materials_; }

 private:
  std::vector<Material> materials_;
};

/// A polygon (outer ring + holes, local frame, metres) assigning one material.
struct MaterialPolygon {
  std::vector<std::vector<Eigen::Vector2d>> rings;  ///< first = outer ring; others = holes
  std::uint16_t material = 0;
  Eigen::Vector4d bbox = Eigen::Vector4d::Zero();  ///< min x, min y, max x, max y (computed)
  /// Even-odd rule over all rings.
  bool contains(const Eigen::Vector2d& p) const;
  void compute_bbox();
};

/// A classification raster: one material index per cell (nearest-cell lookup), or kNoClass.
struct ClassRaster {
  static constexpr std::uint16_t kNoClass = 0xFFFF;
  GridGeometry geometry;               ///< cell centres, as for HeightGrid
  std::vector<std::uint16_t> classes;  ///< material index per cell, row-major; kNoClass = unset
  std::uint16_t at(double x_m, double y_m) const;
};

/// Where each material lies on the seabed: polygons (later ones win) over a classification
/// raster over a default material.
class MaterialMap {
 public:
  explicit MaterialMap(std::uint16_t default_material = 0) : default_(default_material) {}
  void set_default(std::uint16_t m) { default_ = m; }
  void set_raster(ClassRaster raster) { raster_ = std::move(raster); }
  void add_polygon(MaterialPolygon polygon);

  std::uint16_t material_at(double x_m, double y_m) const;
  std::uint16_t default_material() const { return default_; }
  std::size_t polygon_count() const { return polygons_.size(); }
  /// True if every point has the default material (lets the renderer skip look-ups).
  bool uniform() const { return polygons_.empty() && raster_.classes.empty(); }

 private:
  std::uint16_t default_;
  ClassRaster raster_;
  std::vector<MaterialPolygon> polygons_;
};

}  // namespace sonarsynth
