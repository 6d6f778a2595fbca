// SPDX-License-Identifier: MIT
#include "sonarsynth/material.hpp"

#include <algorithm>
#include <cmath>

#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace {
double from_db(double db) {
  return std::pow(10.0, db / 10.0);
}
}  // namespace

void Material::validate() const {
  // Built only on failure: render_side validates its materials on every ping.
  const auto where = [this] { return "material '" + name + "': "; };
  if (name.empty()) throw InputError("material: empty name");
  if (!(lambert_mu > 0.0 && lambert_mu <= 1.0)) {
    throw InputError(where() + "lambert_mu = " + std::to_string(lambert_mu) +
                     ". Violated constraint: 0 < lambert_mu <= 1");
  }
  if (!(paper_reflectivity >= 0.0 && paper_reflectivity <= 1.0)) {
    throw InputError(where() + "reflectivity = " + std::to_string(paper_reflectivity) +
                     ". Violated constraint: 0 <= reflectivity <= 1");
  }
  if (!(texture_shape_nu >= 0.0) || !std::isfinite(texture_shape_nu)) {
    throw InputError(where() + "texture_shape = " + std::to_string(texture_shape_nu) +
                     ". Violated constraint: texture_shape >= 0 (0 = none)");
  }
  if (!(roughness_rms_m >= 0.0 && roughness_rms_m <= 10.0)) {
    throw InputError(where() + "roughness_rms_m = " + std::to_string(roughness_rms_m) +
                     ". Violated constraint: 0 <= roughness_rms_m <= 10 (0 = smooth)");
  }
  if (!(roughness_length_m >= 1e-4 && roughness_length_m <= 1e3)) {
    throw InputError(where() + "roughness_length_m = " + std::to_string(roughness_length_m) +
                     ". Violated constraint: 1e-4 <= roughness_length_m <= 1000");
  }
  if (!(specular_rho >= 0.0 && specular_rho <= 1.0)) {
    throw InputError(where() + "specular_rho = " + std::to_string(specular_rho) +
                     ". Violated constraint: 0 <= specular_rho <= 1 (0 = no glint)");
  }
  if (!(specular_rms_slope > 0.0 && specular_rms_slope <= 1.0)) {
    throw InputError(where() + "specular_rms_slope = " + std::to_string(specular_rms_slope) +
                     ". Violated constraint: 0 < specular_rms_slope <= 1");
  }
}

MaterialTable MaterialTable::defaults() {
  // Lambert mu chosen so that BS at 30-45 deg grazing (mu sin^2 g, ~ -4 dB) falls at the
  // midpoints of the ranges in docs/physics.md §1.5: mud -35, sand -25, gravel -20, rock -15 dB.
  MaterialTable t;
  t.set({.name = "mud",
         .lambert_mu = from_db(-31.0),
         .paper_reflectivity = 0.25,
         .texture_shape_nu = 0.0});
  t.set({.name = "sand",
         .lambert_mu = from_db(-21.0),
         .paper_reflectivity = 0.5,
         .texture_shape_nu = 20.0});
  t.set({.name = "gravel",
         .lambert_mu = from_db(-16.0),
         .paper_reflectivity = 0.7,
         .texture_shape_nu = 5.0});
  t.set({.name = "rock",
         .lambert_mu = from_db(-11.0),
         .paper_reflectivity = 0.85,
         .texture_shape_nu = 2.0});
  // Objects (docs/physics.md §1.11): a K texture of few scatterers per cell (welds, rivets,
  // pits, fouling on steel; aggregate and spalls on concrete, more uneven), resolved roughness
  // of dents and plate waviness (1 cm over 0.3 m on steel, 1 cm over 0.2 m on concrete: facets
  // tilt by ~ sigma / L = 2-3 deg) and a glint lobe: rho = |R|^2 / pi with the plane-wave
  // reflection coefficient R = (Z - Zw) / (Z + Zw) (steel Z = 46 MRayl: -5.5 dB; concrete
  // 8.5 MRayl: -8 dB) and unresolved slopes of 0.1 (steel) and 0.15 rad (concrete).
  t.set({.name = "steel",
         .lambert_mu = from_db(-8.0),
         .paper_reflectivity = 1.0,
         .texture_shape_nu = 10.0,
         .roughness_rms_m = 0.01,
         .roughness_length_m = 0.3,
         .specular_rho = from_db(-5.5),
         .specular_rms_slope = 0.1});
  t.set({.name = "concrete",
         .lambert_mu = from_db(-10.0),
         .paper_reflectivity = 0.9,
         .texture_shape_nu = 5.0,
         .roughness_rms_m = 0.01,
         .roughness_length_m = 0.2,
         .specular_rho = from_db(-8.0),
         .specular_rms_slope = 0.15});
  return t;
}

std::uint16_t MaterialTable::set(const Material& m) {
  m.validate();
  for (std::size_t i = 0; i < materials_.size(); ++i) {
    if (materials_[i].name == m.name) {
      materials_[i] = m;
      return static_cast<std::uint16_t>(i);
    }
  }
  if (materials_.size() >= ClassRaster::kNoClass) throw InputError("material: too many materials");
  materials_.push_back(m);
  return static_cast<std::uint16_t>(materials_.size() - 1);
}

bool MaterialTable::contains(const std::string& name) const {
  return std::any_of(materials_.begin(), materials_.end(),
                     [&](const Material& m) { return m.name == name; });
}

std::uint16_t MaterialTable::index_of(const std::string& name) const {
  for (std::size_t i = 0; i < materials_.size(); ++i) {
    if (materials_[i].name == name) return static_cast<std::uint16_t>(i);
  }
  std::string known;
  for (const Material& m : materials_) known += (known.empty() ? "" : ", ") + m.name;
  throw InputError("unknown material '" + name + "' (known: " + known + ")");
}

void MaterialPolygon::compute_bbox() {
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (const auto& ring : rings) {
    for (const Eigen::Vector2d& p : ring) {
      x0 = std::min(x0, p.x());
      y0 = std::min(y0, p.y());
      x1 = std::max(x1, p.x());
      y1 = std::max(y1, p.y());
    }
  }
  bbox = {x0, y0, x1, y1};
}

bool MaterialPolygon::contains(const Eigen::Vector2d& p) const {
  if (p.x() < bbox[0] || p.y() < bbox[1] || p.x() > bbox[2] || p.y() > bbox[3]) return false;
  bool inside = false;
  for (const auto& ring : rings) {
    const std::size_t n = ring.size();
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
      const Eigen::Vector2d& a = ring[i];
      const Eigen::Vector2d& b = ring[j];
      if ((a.y() > p.y()) != (b.y() > p.y()) &&
          p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
        inside = !inside;
      }
    }
  }
  return inside;
}

std::uint16_t ClassRaster::at(double x_m, double y_m) const {
  if (classes.empty()) return kNoClass;
  const double c = std::round(geometry.col_of_x(x_m));
  const double r = std::round(geometry.row_of_y(y_m));
  if (!(c >= 0 && r >= 0 && c < static_cast<double>(geometry.cols) &&
        r < static_cast<double>(geometry.rows))) {
    return kNoClass;
  }
  return classes[static_cast<std::size_t>(r) * geometry.cols + static_cast<std::size_t>(c)];
}

void MaterialMap::add_polygon(MaterialPolygon polygon) {
  polygon.compute_bbox();
  polygons_.push_back(std::move(polygon));
}

std::uint16_t MaterialMap::material_at(double x_m, double y_m) const {
  const Eigen::Vector2d p(x_m, y_m);
  for (auto it = polygons_.rbegin(); it != polygons_.rend(); ++it) {
    if (it->contains(p)) return it->material;
  }
  const std::uint16_t c = raster_.at(x_m, y_m);
  return c == ClassRaster::kNoClass ? default_ : c;
}

}  // namespace sonarsynth
