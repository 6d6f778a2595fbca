// SPDX-License-Identifier: MIT
// The last stage of render_side (lib/render_side.cpp): the fine range bins gathered into the
// output samples, with the truth of each sample (class, label, material, grazing angle, ground
// point) from its dominant fine bin.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>

#include "sonarsynth/render_kernel.hpp"
#include "sonarsynth/render_math.hpp"
#include "sonarsynth/render_side.hpp"
#include "sonarsynth/simd.hpp"

namespace sonarsynth::render_gather {

using render_math::atan_poly;

// The first fine bin of a seabed return (nf if none): a target in mid-water (a section) has
// water column behind it.
inline std::ptrdiff_t first_seabed_return(const BeamProfile& prof, const SideEcho::Workspace& w) {
  const std::ptrdiff_t nf = static_cast<std::ptrdiff_t>(w.fine_energy.size());
  const auto seabed_facets = static_cast<std::int32_t>(prof.seabed_facets());
  for (std::ptrdiff_t j = 0; j < nf; ++j) {
    const auto u = static_cast<std::size_t>(j);
    if (w.fine_energy[u] > 0.0 && (prof.sections() == 0 || w.best_facet[u] < seabed_facets)) {
      return j;
    }
  }
  return nf;
}

// The slope angle alpha = atan2(uz, uy) of profile facet k. Seabed facets are mostly flat to a
// tenth: the series there, atan2 otherwise.
inline double facet_slope_rad(const BeamProfile& prof, std::size_t k) {
  double ya, za, yb, zb;
  prof.facet_ends(k, ya, za, yb, zb);
  const double uy = yb - ya, uz = zb - za;
  if (uy > 0.0 && std::abs(uz) < 0.1 * uy) {
    const double x = uz / uy;
    return x * atan_poly(x * x, 8);  // |x|^17 / 17 < 6e-19
  }
  return std::atan2(uz, uy);
}

// Grazing angles without asin per sample: with the depression theta of the midpoint
// (atan2(-mz, my)) and the facet's slope angle alpha = atan2(uz, uy), cos(incidence) =
// -n.(my, mz) / r = sin(theta + alpha) for the upward unit normal n, so asin(clamp(cos_inc,
// 0, 1)) = theta + alpha folded into [0, pi/2]. theta = theta_ref + atan(x) from a reference
// midpoint (x = tan of the angle between the two rays, truncated series of render_math where
// |x| < 0.1), atan2 otherwise (which becomes the new reference). The reference is any earlier
// midpoint, of this facet or another.
struct GrazingSeries {
  bool have_ref = false;
  double ref_y = 0.0, ref_z = 0.0, ref_theta = 0.0;

  // The grazing angle at midpoint (my, mz) of a facet of slope alpha (0 at the sensor).
  [[gnu::always_inline]] double angle_rad(double alpha, double my, double mz) {
    if (!(my * my + mz * mz > 0.0)) return 0.0;
    double theta = 0.0;
    const double cross = ref_z * my - ref_y * mz, dot = ref_y * my + ref_z * mz;
    if (have_ref && dot > 0.0 && std::abs(cross) < 0.01 * dot) {
      const double x = cross / dot;
      theta = ref_theta + x * atan_poly(x * x, 4);  // |x|^9 / 9 < 1.2e-19
    } else if (have_ref && dot > 0.0 && std::abs(cross) < 0.1 * dot) {
      const double x = cross / dot;
      theta = ref_theta + x * atan_poly(x * x, 8);  // |x|^17 / 17 < 6e-19
    } else {
      theta = std::atan2(-mz, my);
      have_ref = true;
      ref_y = my;
      ref_z = mz;
      ref_theta = theta;
    }
    double g = theta + alpha;  // in (-2 pi, 2 pi]: reduce to (-pi, pi], then fold
    if (g > std::numbers::pi) g -= 2.0 * std::numbers::pi;
    if (g <= -std::numbers::pi) g += 2.0 * std::numbers::pi;
    if (g > 0.5 * std::numbers::pi) g = std::numbers::pi - g;
    return std::max(g, 0.0);
  }
};

// Sample i <- fine bins [first(i), last(i)] (clipped at 0).
template <bool kTruth, class Window>
void gather(const BeamProfile& prof, const SideParams& par, bool any_valid, Window window,
            SideEcho& out) {
  auto& w = out.workspace;
  const std::size_t ns = par.samples;
  std::ptrdiff_t first_return = static_cast<std::ptrdiff_t>(w.fine_energy.size());
  if constexpr (kTruth) first_return = first_seabed_return(prof, w);
  const bool grazing = par.truth_grazing;
  // The vector targets fill the grazing angles after the loop (render_kernel::grazing_angles):
  // the loop leaves each contributor's facet slope alpha in truth_grazing_rad and its dz in
  // w.sample_dz_m. The scalar target keeps the series (GrazingSeries, the reference).
  const bool vector_grazing = kTruth && grazing && simd::active_target() != simd::Target::scalar;
  if (vector_grazing) w.sample_dz_m.resize(ns);
  std::int32_t facet = -1;  // facet of the cached slope, label and material
  double alpha = 0.0;
  GrazingSeries series;
  std::int32_t label = 0;
  std::uint16_t material = 0;
  for (std::size_t i = 0; i < ns; ++i) {
    const auto [j0, j1] = window(static_cast<std::ptrdiff_t>(i));
    double sum = 0.0;
    std::ptrdiff_t jbest = -1;
    std::int32_t caster = -1;  // of the hidden parts in the window (-1: none)
    for (std::ptrdiff_t j = std::max<std::ptrdiff_t>(0, j0); j <= j1; ++j) {
      const auto u = static_cast<std::size_t>(j);
      sum += w.fine_energy[u];
      if constexpr (kTruth) {
        if (w.best_energy[u] > 0.0 &&
            (jbest < 0 || w.best_energy[u] > w.best_energy[static_cast<std::size_t>(jbest)])) {
          jbest = j;
        }
        caster = std::max(caster, w.shadow_caster[u]);
      }
    }
    out.intensity[i] = sum;
    if constexpr (!kTruth) continue;
    if (jbest < 0) {
      out.truth_class[i] = caster >= 0                        ? SampleClass::shadow
                           : (j1 < first_return && any_valid) ? SampleClass::water_column
                                                              : SampleClass::no_seabed;
      out.truth_label[i] = caster;  // a shadow's caster (0 relief, > 0 object id), else -1
      out.truth_material[i] = 0;
      constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
      if (grazing) out.truth_grazing_rad[i] = kNaN;
      out.truth_ground_y_m[i] = kNaN;
      out.truth_ground_z_m[i] = kNaN;
      continue;
    }
    // The dominant sub-piece's midpoint (my, mz) relative to the sensor; the normal of its
    // facet is computed once per run of samples sharing the facet.
    const auto b = static_cast<std::size_t>(jbest);
    const std::int32_t fi = w.best_facet[b];
    if (fi != facet) {
      facet = fi;
      const auto k = static_cast<std::size_t>(fi);
      if (grazing) alpha = facet_slope_rad(prof, k);
      label = prof.facet_label(k);
      material = prof.facet_material(k);
    }
    const double my = w.best_y_m[b], mz = w.best_dz_m[b];
    out.truth_class[i] = label > 0 ? SampleClass::object : SampleClass::seabed;
    out.truth_label[i] = label;
    out.truth_material[i] = material;
    if (vector_grazing) {
      out.truth_grazing_rad[i] = alpha;
      w.sample_dz_m[i] = mz;
    } else if (grazing) {
      out.truth_grazing_rad[i] = series.angle_rad(alpha, my, mz);
    }
    out.truth_ground_y_m[i] = my;
    out.truth_ground_z_m[i] = mz + prof.sensor_z_m;
  }
  if (vector_grazing) {
    render_kernel::grazing_angles(out.truth_ground_y_m.data(), w.sample_dz_m.data(),
                                  out.truth_grazing_rad.data(), ns);
  }
}

}  // namespace sonarsynth::render_gather
