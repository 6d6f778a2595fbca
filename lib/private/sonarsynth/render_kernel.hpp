// SPDX-License-Identifier: MIT
// The vector kernel of the per-side renderer (lib/render_kernel.cpp; docs/physics.md §2.1):
// a monotone piece of a facet cut at the bin edges and integrated by its Gauss rule, one range
// bin per lane, in the instruction set chosen at run time (sonarsynth/simd.hpp). Internal.
#pragma once

#include <cstddef>
#include <cstdint>

namespace sonarsynth::render_kernel {

// Lanes of the widest target compiled (AVX-512 doubles): output arrays hold this many more
// entries than bins.
constexpr std::size_t kMaxLanes = 8;

// One monotone piece [s0, s1] of the facet A + t u (render_facet::Facet, render_piece) over the
// bins [j_lo, j_hi], with what the integrand at a point depends on (render_facet::Integrand).
struct PieceArgs {
  // The facet, relative to the sensor: A = (ay, az_rel); |u|; r(t)^2 = a (t - tm0)^2 + p2.
  double ay, az_rel, uy, uz, len_m, tm0, p2, inv_a;
  double coef;  // energy factor (Facet::coef)
  // Depression of P(t) - S: theta_a - atan(x), x = t cross / (w2 + t wu) by its series of
  // series_terms terms where the facet allows (Facet::depression); atan2 where series_terms = 0.
  double theta_off, cross, w2, wu;
  int series_terms;
  double max_piece_over_range;  // longer sub-pieces are left to the caller (Facet)
  // The piece: range increasing along t (branch +1) or decreasing (-1); r1 = r(s1).
  double s0, s1, r1, branch;
  std::ptrdiff_t j_s0;  // the bin whose sub-piece starts at s0 (-1: none, it starts at a root)
  // Bin edges: j dr (uniform) or the split grid's (render_facet::SplitGrid, split_f > 0).
  double dr, split_f;
  // The integrand (render_facet::Integrand).
  double axis_rad, gauss_coef, kappa_per_m;
  bool spreading, paper;
  double paper_upper_rad, paper_lower_rad;
  int gauss_points;
  const double* gauss_x;  // rule points on [0, 1]
  const double* gauss_w;  // their weights
};

// For every bin j in [j_lo, j_hi] (k = j - j_lo): the sub-piece [lo, hi] of the piece in the
// bin (cut at the roots r(t) = bin edge), its energy e[k] by the Gauss rule (as
// render_facet::integrate: sum of w b^2 e^(-kappa r) / r^5 times dl coef; 0 for an empty
// sub-piece), added to energy[j], and its midpoint (my[k], mz[k]) relative to the sensor. A
// sub-piece longer than max_piece_over_range of its range is not integrated: e[k] = NaN, its
// ends in lo[k], hi[k], for the caller to subdivide. Returns the number of those. The output
// arrays hold j_hi - j_lo + 1 + kMaxLanes entries. Dispatched to the target simd::set_target
// allows (the EMU128 copy is the scalar reference).
std::size_t render_bins(const PieceArgs& a, std::ptrdiff_t j_lo, std::ptrdiff_t j_hi,
                        double* energy, double* e, double* my, double* mz, double* lo, double* hi);

// The truth's grazing angle per sample (render_side's gather): g[i] on entry is the slope angle
// alpha of the contributing facet (NaN: no contributor, left as it is), (y[i], dz[i]) the
// contributor relative to the sensor; on return g[i] = the depression atan2(-dz, y) plus alpha,
// folded into [0, pi/2] (0 at the sensor itself). Dispatched as render_bins.
void grazing_angles(const double* y, const double* dz, double* g, std::size_t n);

}  // namespace sonarsynth::render_kernel
