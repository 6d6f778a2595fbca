// SPDX-License-Identifier: MIT
// The facet integrator of the per-side renderer (lib/render_side.cpp; docs/physics.md §2.1):
// range-bin grids, the integrand's constants, a visible linear facet, and the exact clipping of
// a facet piece into range bins with its Gauss sums. Internal: included by render_side.cpp only,
// so that everything here inlines into the sweep as it did in one file.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sonarsynth/backscatter.hpp"
#include "sonarsynth/render_kernel.hpp"
#include "sonarsynth/render_math.hpp"
#include "sonarsynth/render_side.hpp"

namespace sonarsynth::render_facet {

using namespace render_math;

// Slant-range bins of width dr: bin j = [j dr, (j + 1) dr), j = 0 .. n - 1.
struct UniformGrid {
  double dr;
  double inv_dr;
  std::ptrdiff_t n;
  double edge(std::ptrdiff_t j) const { return static_cast<double>(j) * dr; }
  std::ptrdiff_t index(double r) const {
    return static_cast<std::ptrdiff_t>(std::floor(r * inv_dr));
  }
};

// Bins split at k dr and at (k + 1) dr - f (0 < f < dr), for a pulse window w = m dr + f:
// fine bin 2k = [k dr, (k + 1) dr - f), fine bin 2k + 1 = [(k + 1) dr - f, (k + 1) dr).
struct SplitGrid {
  double dr;
  double inv_dr;
  double f;
  std::ptrdiff_t n;  // 2 * samples
  double edge(std::ptrdiff_t j) const {
    const double k = static_cast<double>(j >> 1);
    return (j & 1) ? (k + 1.0) * dr - f : k * dr;
  }
  std::ptrdiff_t index(double r) const {
    const auto k = static_cast<std::ptrdiff_t>(std::floor(r * inv_dr));
    return 2 * k + ((r >= static_cast<double>(k + 1) * dr - f) ? 1 : 0);
  }
};

// Per-call constants of the integrand.
struct Integrand {
  double sensor_z_m;
  double axis_rad;
  const VerticalBeamPattern* beam;  // non-Gaussian, non-uniform patterns; else nullptr
  double gauss_coef;                // Gaussian two-way b^2 = exp(-gauss_coef off^2); 0 = none
  bool spreading;
  double kappa_per_m;  // 2 alpha ln(10) / 10 (two-way, nepers of intensity per metre); 0 = off
  const GaussRule* rule;
  // Off-axis angles where the beam is not smooth, increasing (docs/physics.md §2.1 step 4): the
  // paper sine pair's edges and axis, a table's angles; empty for smooth beams.
  std::span<const double> kinks;
  // The beam is 0 outside [lit_lo, lit_hi] (off-axis, radians): the paper sine pair.
  double lit_lo, lit_hi;
  // The paper sine pair (then also in beam), evaluated inline by paper_one_way: its half-widths
  // above (off < 0) and below the axis.
  bool paper;
  double paper_upper_rad, paper_lower_rad;
};

// VerticalBeamPattern::one_way of the paper sine pair.
inline double paper_one_way(const Integrand& in, double off) {
  return paper_sine_pair(off, in.paper_upper_rad, in.paper_lower_rad);
}

// The kinks of a beam (Integrand::kinks), in `storage` (3 entries) or the table itself.
inline std::span<const double> beam_kinks(const VerticalBeamPattern& b, double (&storage)[3]) {
  if (b.shape == VerticalBeamShape::paper_sine_pair) {
    storage[0] = -b.upper_half_width_rad;
    storage[1] = 0.0;
    storage[2] = b.lower_half_width_rad;
    return storage;
  }
  if (b.shape == VerticalBeamShape::table) return b.table_off_axis_rad;
  return {};
}

// One visible linear facet A + t u, t in [0, 1].
struct Facet {
  double ay, az, uy, uz;  // start and direction
  double len_m;           // |u|
  double a, tm0, p2;      // r(t)^2 = a (t - tm0)^2 + p2 (p = distance of the facet's line)
  double inv_a;           // 1 / a
  // K beta_eff sigma-coefficient of the material times c0^2, where c0 = -n . (P - S) = cross /
  // |u| is constant along the facet (n is normal to u): cos(incidence) = c0 / r at every point.
  double coef;
  // Depression of P(t) - S relative to that of w = A - S: theta(t) = theta_a - atan(x),
  // x = t cross / (w2 + t wu) (angle between w and w + t u), see depression().
  double theta_a, w2, wu, cross;
  double az_rel;     // az - Hs
  double theta_off;  // theta_a - beam axis depression
  // Terms of the atan series valid on the whole facet (1 .. 8), 0 if the series is not valid
  // everywhere on it (then the per-point test below decides).
  int series_terms;
  std::int32_t index;  // facet index in the profile
  // Object glint (docs/physics.md §1.11), 0 = none: K beta_eff c0^2, so that a point's
  // specular energy is glint_coef sigma_s(sec^2) sec^2 times the Lambert integrand's point
  // factor (sigma_s r / r^4 = sigma_s sec^2 c0^2 / r^5, sec^2 = r^2 / c0^2); 1 / c0^2; the lobe.
  double glint_coef;
  double inv_c02;
  KirchhoffLobe lobe;
  // Longest sub-piece of one Gauss rule relative to its range (kMaxPieceOverRange, or less for a
  // narrow glint lobe).
  double max_piece_over_range;
  double range(double t) const {
    const double d = t - tm0;
    return std::sqrt(std::max(0.0, a * d * d + p2));
  }
  // Depression atan2(-(P_z - Hs), P_y) of P(t) without atan2 per point: the angle subtended by
  // a sub-metre facet seen from metres away is small, so atan(x) is its odd Taylor series,
  // truncated per facet where the first omitted term is below kAtanTolerance (at most to x^15:
  // |x| < 0.1, 0.1^17 / 17 < 1e-18); libm otherwise.
  double depression(double t, double py, double dz) const {
    const double den = w2 + t * wu;
    const double num = t * cross;
    if (series_terms > 0) {
      const double x = num / den;
      return theta_a - x * atan_poly(x * x, series_terms);
    }
    if (den > 0.0 && std::abs(num) < 0.1 * den) {
      const double x = num / den;
      return theta_a - x * atan_poly(x * x, 8);
    }
    return std::atan2(-dz, py);
  }
  // Parameter where r(t) = e on the branch after (+1) or before (-1) the range minimum.
  double root(double e, double branch) const {
    return tm0 + branch * std::sqrt(std::max(0.0, (e * e - p2) * inv_a));
  }
  // Decides series_terms: x(t) = t cross / (w2 + t wu) is monotone on [0, 1] when its
  // denominator stays positive (a Moebius map without pole there), and |num| < 0.1 den, linear
  // on both sides, holds on [0, 1] iff it holds at both ends; so |x| <= |x(1)| on the facet.
  void set_series_terms() {
    const double den1 = w2 + wu;
    series_terms = (w2 > 0.0 && den1 > 0.0 && std::abs(cross) < 0.1 * den1)
                       ? atan_terms(std::abs(cross) / den1)
                       : 0;
  }
};

struct Workspace {
  double* energy;
  double* best;
  std::int32_t* best_facet;
  double* best_y;
  double* best_dz;
  // The vector kernel's integrand and grid (render_kernel::render_bins; the facet and piece
  // fields are filled per piece), for the beams it evaluates: uniform, Gaussian and the paper
  // sine pair; nullptr: every sub-piece by the scalar gauss_sum.
  const render_kernel::PieceArgs* kernel;
};

// The split grid's f for the vector kernel (0: a uniform grid).
inline double split_width(const UniformGrid&) {
  return 0.0;
}
inline double split_width(const SplitGrid& g) {
  return g.f;
}

// Longest sub-piece integrated by one Gauss rule, relative to its distance from the sensor:
// the integrand varies on the scale of r, so the rule's error ~ (l / r)^4 (near nadir a bin spans
// metres of seabed). 0.02 keeps the 2-point rule below ~1e-9 relative on a flat seabed.
constexpr double kMaxPieceOverRange = 0.02;

#ifdef SONARSYNTH_GAUSS_PAIRS
// Two Gauss points (parameters t, weights w) of the integrand below in the lanes of one vector:
// the same operations as gauss_sum's scalar loop lane by lane. Requires r2 > 0 in both lanes
// (the caller checks), a Gaussian, paper sine pair or uniform beam and, with the first two, the
// atan series valid on the facet (series_terms > 0).
[[gnu::always_inline]] inline V2d gauss_pair(const Facet& f, const Integrand& in, V2d t, V2d w,
                                             V2d r2) {
  const V2d r = sqrt2(r2);
  V2d v = w / (in.spreading ? r2 * r2 * r : r);
  V2d expo = V2d{} + 0.0;
  if (in.gauss_coef > 0.0 || in.paper) {
    const V2d x = (t * f.cross) / (f.w2 + t * f.wu);
    const V2d off = f.theta_off - x * atan_poly(x * x, f.series_terms);
    if (in.gauss_coef > 0.0) {
      expo -= in.gauss_coef * off * off;
    } else {  // paper_one_way lane by lane
      const V2d u = off / V2d{off[0] < 0.0 ? in.paper_upper_rad : in.paper_lower_rad,
                              off[1] < 0.0 ? in.paper_upper_rad : in.paper_lower_rad};
      const V2d au = {std::abs(u[0]), std::abs(u[1])};
      V2d b = sin_series_half_pi(kHalfPi * (1.0 - au));
      if (au[0] >= 1.0) b[0] = 0.0;
      if (au[1] >= 1.0) b[1] = 0.0;
      v *= b * b;
    }
  }
  if (in.kappa_per_m > 0.0) expo -= in.kappa_per_m * r;
  if (in.gauss_coef > 0.0 || in.kappa_per_m > 0.0) v *= exp_table2(expo);
  return v;
}
#endif

// Gauss–Legendre sum over [q0, q1] (in t) of the integrand without the arc-length factor and
// without f.coef; kGlint: with f.coef and the facet's glint, coef + glint_coef sigma_s sec^2 per
// point (scalar loop only).
template <bool kGlint = false>
[[gnu::always_inline]] inline double gauss_sum(const Facet& f, const Integrand& in, double q0,
                                               double dq) {
  const GaussRule& rule = *in.rule;
  double sum = 0.0;
  int g = 0;
#ifdef SONARSYNTH_GAUSS_PAIRS
  if (!kGlint && (in.beam == nullptr || in.paper) &&
      (f.series_terms > 0 || !(in.gauss_coef > 0.0 || in.paper))) {
    if (rule.n == 2) {
      // The default rule: one pair, no loop (its loop-invariant set-up cost as much as the pair).
      // The same operations as the loop below: bit-identical sums.
      constexpr GaussRule kTwo = kRules[1];
      const V2d t = q0 + V2d{kTwo.x[0], kTwo.x[1]} * dq;
      const V2d py = f.ay + t * f.uy;
      const V2d dz = f.az_rel + t * f.uz;
      const V2d r2 = py * py + dz * dz;
      if (r2[0] > 0.0 && r2[1] > 0.0) {
        const V2d v = gauss_pair(f, in, t, V2d{kTwo.w[0], kTwo.w[1]}, r2);
        sum += v[0];
        sum += v[1];
        return sum;
      }
    }
    for (; g + 1 < rule.n; g += 2) {
      const V2d t = q0 + V2d{rule.x[g], rule.x[g + 1]} * dq;
      const V2d py = f.ay + t * f.uy;
      const V2d dz = f.az_rel + t * f.uz;
      const V2d r2 = py * py + dz * dz;
      if (!(r2[0] > 0.0 && r2[1] > 0.0)) break;  // a point at the sensor: scalar loop
      const V2d v = gauss_pair(f, in, t, V2d{rule.w[g], rule.w[g + 1]}, r2);
      sum += v[0];
      sum += v[1];
    }
  }
#endif
  for (; g < rule.n; ++g) {
    const double t = q0 + rule.x[g] * dq;
    const double py = f.ay + t * f.uy;
    const double dz = f.az + t * f.uz - in.sensor_z_m;  // P_z - Hs
    const double r2 = py * py + dz * dz;
    if (!(r2 > 0.0)) continue;
    const double r = std::sqrt(r2);
    // sigma = coef' cos^2(phi) = coef' c0^2 / r^2 (c0^2 in f.coef); along-track extent r beta
    // (beta in coef): w r / r^2 (/ r^4 with spreading).
    double v = rule.w[g] / (in.spreading ? r2 * r2 * r : r);
    // Gaussian beam and absorption share one exp().
    double expo = 0.0;
    if (in.gauss_coef > 0.0) {
      const double off = f.depression(t, py, dz) - in.axis_rad;
      expo -= in.gauss_coef * off * off;
    } else if (in.paper) {
      const double b = paper_one_way(in, f.depression(t, py, dz) - in.axis_rad);
      v *= b * b;
    } else if (in.beam != nullptr) {
      v *= in.beam->two_way(f.depression(t, py, dz) - in.axis_rad);
    }
    if (in.kappa_per_m > 0.0) expo -= in.kappa_per_m * r;
    if (expo != 0.0) v *= exp_table(expo);
    if constexpr (kGlint) {
      const double sec2 = r2 * f.inv_c02;
      v *= f.coef + f.glint_coef * f.lobe.sigma_of_sec2(sec2) * sec2;
    }
    sum += v;
  }
  return sum;
}

template <bool kGlint>
inline double piece_sum(const Facet& f, const Integrand& in, double q0, double dq, double dl,
                        double rmid2) {
  const double lim = f.max_piece_over_range;
  if (dl * dl <= lim * lim * rmid2) return gauss_sum<kGlint>(f, in, q0, dq);
  const double parts = std::ceil(dl / (lim * std::sqrt(rmid2)));
  const int n = static_cast<int>(std::min(parts, 4096.0));
  const double h = dq / static_cast<double>(n);
  double sum = 0.0;
  for (int k = 0; k < n; ++k) sum += gauss_sum<kGlint>(f, in, q0 + static_cast<double>(k) * h, h);
  return sum / static_cast<double>(n);
}

// Integrates the sub-piece [q0, q1] of facet f into fine bin j.
template <bool kTruth>
inline void integrate(const Facet& f, const Integrand& in, double q0, double q1, std::ptrdiff_t j,
                      const Workspace& ws) {
  const double dq = q1 - q0;
  if (!(dq > 0.0)) return;
  const double dl = dq * f.len_m;
  const double tmid = 0.5 * (q0 + q1);
  const double my = f.ay + tmid * f.uy, mz = f.az + tmid * f.uz - in.sensor_z_m;
  const double rmid2 = my * my + mz * mz;
  const double e = f.glint_coef > 0.0 ? piece_sum<true>(f, in, q0, dq, dl, rmid2) * dl
                                      : piece_sum<false>(f, in, q0, dq, dl, rmid2) * dl * f.coef;
  ws.energy[j] += e;
  if constexpr (kTruth) {
    if (e > ws.best[j]) {
      ws.best[j] = e;
      ws.best_facet[j] = f.index;
      ws.best_y[j] = my;
      ws.best_dz[j] = mz;
    }
  }
}

// render_piece by the vector kernel (ws.kernel, a facet without glint): the same bins, cuts and
// sub-pieces, the bins in lanes (docs/physics.md §2.1). Sub-pieces too long for one Gauss rule
// (near nadir) are subdivided by the scalar integrate().
template <bool kTruth, class Grid>
void render_piece_bins(const Facet& f, const Integrand& in, const Grid& grid, double s0, double s1,
                       double r0, double r1, double branch, const Workspace& ws) {
  const double r_max = grid.edge(grid.n);
  const auto start_bin = [&] {
    std::ptrdiff_t j = std::max<std::ptrdiff_t>(0, grid.index(r0));
    while (j > 0 && grid.edge(j) > r0) --j;
    while (j + 1 < grid.n && grid.edge(j + 1) <= r0) ++j;
    return j;
  };
  std::ptrdiff_t j_lo = 0, j_hi = 0, j_s0 = -1;
  if (branch > 0) {
    // From r0's bin up to the first bin whose upper edge reaches r1 (the last bin at most).
    if (r0 >= r_max) return;
    j_lo = j_s0 = start_bin();
    std::ptrdiff_t k = r1 >= r_max ? grid.n - 1 : std::clamp(grid.index(r1), j_lo, grid.n - 1);
    while (k > j_lo && grid.edge(k) >= r1) --k;
    while (k + 1 < grid.n && grid.edge(k + 1) < r1) ++k;
    j_hi = k;
  } else {
    // From r0's bin (the last bin if r0 is beyond it) down to the last bin whose lower edge is
    // at or below r1 (bin 0 at least).
    if (r1 >= r_max) return;
    if (r0 >= r_max) {
      j_hi = grid.n - 1;
    } else {
      j_hi = j_s0 = start_bin();
    }
    std::ptrdiff_t k = std::clamp<std::ptrdiff_t>(grid.index(r1), 0, j_hi);
    while (k < j_hi && grid.edge(k + 1) <= r1) ++k;
    while (k > 0 && grid.edge(k) > r1) --k;
    j_lo = k;
  }
  render_kernel::PieceArgs a = *ws.kernel;
  a.ay = f.ay;
  a.az_rel = f.az_rel;
  a.uy = f.uy;
  a.uz = f.uz;
  a.len_m = f.len_m;
  a.tm0 = f.tm0;
  a.p2 = f.p2;
  a.inv_a = f.inv_a;
  a.coef = f.coef;
  a.theta_off = f.theta_off;
  a.cross = f.cross;
  a.w2 = f.w2;
  a.wu = f.wu;
  a.series_terms = f.series_terms;
  a.max_piece_over_range = f.max_piece_over_range;
  a.s0 = s0;
  a.s1 = s1;
  a.r1 = r1;
  a.branch = branch;
  a.j_s0 = j_s0;
  constexpr std::ptrdiff_t kChunk = 64;
  constexpr std::size_t kSize = kChunk + render_kernel::kMaxLanes;
  double e[kSize], my[kSize], mz[kSize], lo[kSize], hi[kSize];
  for (std::ptrdiff_t c = j_lo; c <= j_hi; c += kChunk) {
    const std::ptrdiff_t c_hi = std::min(j_hi, c + kChunk - 1);
    const std::size_t left = render_kernel::render_bins(a, c, c_hi, ws.energy, e, my, mz, lo, hi);
    if (!kTruth && left == 0) continue;
    for (std::ptrdiff_t j = c; j <= c_hi; ++j) {
      const auto k = static_cast<std::size_t>(j - c);
      if (std::isnan(e[k])) {
        integrate<kTruth>(f, in, lo[k], hi[k], j, ws);
      } else if constexpr (kTruth) {
        const auto u = static_cast<std::size_t>(j);
        if (e[k] > ws.best[u]) {
          ws.best[u] = e[k];
          ws.best_facet[u] = f.index;
          ws.best_y[u] = my[k];
          ws.best_dz[u] = mz[k];
        }
      }
    }
  }
}

// Cuts the monotone piece [s0, s1] of facet f (range increasing if branch = +1, decreasing if
// branch = -1 as t goes from s0 to s1) at every bin edge and integrates each sub-piece.
// Edges are visited in order of t, so no sort is needed.
template <bool kTruth, class Grid>
void render_piece(const Facet& f, const Integrand& in, const Grid& grid, double s0, double s1,
                  double branch, const Workspace& ws) {
  if (!(s1 > s0)) return;
  const double r_max = grid.edge(grid.n);
  const double r0 = f.range(s0);
  const double r1 = f.range(s1);
  if (ws.kernel != nullptr && !(f.glint_coef > 0.0)) {
    render_piece_bins<kTruth>(f, in, grid, s0, s1, r0, r1, branch, ws);
    return;
  }
  if (branch > 0) {
    if (r0 >= r_max) return;
    std::ptrdiff_t j = std::max<std::ptrdiff_t>(0, grid.index(r0));
    while (j > 0 && grid.edge(j) > r0) --j;
    while (j + 1 < grid.n && grid.edge(j + 1) <= r0) ++j;
    double q = s0;
    while (true) {
      const double e = grid.edge(j + 1);
      if (e >= r1) {
        integrate<kTruth>(f, in, q, s1, j, ws);
        return;
      }
      const double qn = std::clamp(f.root(e, branch), q, s1);
      integrate<kTruth>(f, in, q, qn, j, ws);
      q = qn;
      if (++j >= grid.n) return;
    }
  } else {
    // Range falls from r0 (at s0) to r1 (at s1).
    if (r1 >= r_max) return;
    double q = s0;
    std::ptrdiff_t j;
    if (r0 >= r_max) {
      j = grid.n - 1;
      q = std::clamp(f.root(r_max, branch), s0, s1);
    } else {
      j = std::max<std::ptrdiff_t>(0, grid.index(r0));
      while (j > 0 && grid.edge(j) > r0) --j;
      while (j + 1 < grid.n && grid.edge(j + 1) <= r0) ++j;
    }
    while (true) {
      const double e = grid.edge(j);
      if (e <= r1 || j == 0) {
        integrate<kTruth>(f, in, q, s1, j, ws);
        return;
      }
      const double qn = std::clamp(f.root(e, branch), q, s1);
      integrate<kTruth>(f, in, q, qn, j, ws);
      q = qn;
      --j;
    }
  }
}

// Renders the lit part [t0, t1] of facet f, whose slant range is least at tm in [t0, t1]: cut
// at tm (two monotone pieces) and, for a beam with kinks, where the depression crosses
// axis + kink, so that every Gauss rule sees a smooth integrand; pieces where the beam is 0 are
// skipped. The depression is monotone along a straight facet, so the crossings come in the
// order of the kinks (increasing or decreasing) and no sort is needed.
template <bool kTruth, class Grid>
void render_lit(const Facet& f, const Integrand& in, const Grid& grid, double t0, double t1,
                double tm, const Workspace& ws) {
  const auto piece = [&](double a, double b) {
    if (!(b > a)) return;
    if (tm > a && tm < b) {
      render_piece<kTruth>(f, in, grid, a, tm, -1.0, ws);
      render_piece<kTruth>(f, in, grid, tm, b, +1.0, ws);
    } else {
      render_piece<kTruth>(f, in, grid, a, b, b <= tm ? -1.0 : +1.0, ws);
    }
  };
  if (in.kinks.empty()) return piece(t0, t1);
  const auto depression = [&](double t) {
    return t == 0.0 ? f.theta_a : f.depression(t, f.ay + t * f.uy, f.az_rel + t * f.uz);
  };
  const double off0 = depression(t0) - in.axis_rad, off1 = depression(t1) - in.axis_rad;
  const bool rising = off1 > off0;
  const std::size_t nk = in.kinks.size();
  double q = t0;  // start of the current piece
  double q_off = off0;
  for (std::size_t k = 0; k < nk; ++k) {
    const double kink = in.kinks[rising ? k : nk - 1 - k];
    if (!(rising ? (kink > off0 && kink < off1) : (kink < off0 && kink > off1))) continue;
    // P(t) - S = (ay + t uy, az_rel + t uz) is along the ray of depression th = axis + kink:
    // cos(th) (az_rel + t uz) + sin(th) (ay + t uy) = 0.
    const double th = in.axis_rad + kink;
    const double c = std::cos(th), s = std::sin(th);
    const double den = c * f.uz + s * f.uy;
    if (den == 0.0) continue;
    const double t = std::clamp(-(c * f.az_rel + s * f.ay) / den, q, t1);
    // Between two kinks the beam is 0 everywhere or nowhere: test the middle of the angles.
    const double mid_off = 0.5 * (q_off + kink);
    if (mid_off > in.lit_lo && mid_off < in.lit_hi) piece(q, t);
    q = t;
    q_off = kink;
  }
  const double mid_off = 0.5 * (q_off + off1);
  if (mid_off > in.lit_lo && mid_off < in.lit_hi) piece(q, t1);
}

// Marks the fine bins spanned by the hidden part [h0, h1] of a facet as shadow cast by `caster`
// (truth only: the occluder's label, 0 seabed relief, > 0 object id). A bin hidden by several
// occluders keeps the largest label, so an object wins over relief (docs/labels.md).
template <class Grid>
void mark_shadow(const Facet& f, const Grid& grid, double h0, double h1, std::int32_t caster,
                 std::vector<std::int32_t>& shadow_caster) {
  if (!(h1 > h0)) return;
  const double tm = std::clamp(f.tm0, h0, h1);
  const double ra = f.range(h0), rb = f.range(h1), rm = f.range(tm);
  const double lo = std::min({ra, rb, rm});
  const double hi = std::max({ra, rb, rm});
  if (lo >= grid.edge(grid.n)) return;
  const std::ptrdiff_t j0 = std::max<std::ptrdiff_t>(0, grid.index(lo));
  const std::ptrdiff_t j1 = std::min<std::ptrdiff_t>(grid.n - 1, grid.index(hi));
  for (std::ptrdiff_t j = j0; j <= j1; ++j) {
    std::int32_t& c = shadow_caster[static_cast<std::size_t>(j)];
    c = std::max(c, caster);
  }
}

// The facet A -> B (absolute coordinates) of the integrand; returns c0 = cos(incidence) r (> 0
// iff it faces the sensor); f.a = 0 for a zero-length facet (then nothing else is set).
inline double setup_facet(Facet& f, const Integrand& in, double hs, double ya, double za, double yb,
                          double zb, std::int32_t index, double coef_per_c0sq) {
  f.ay = ya;
  f.az = za;
  f.uy = yb - ya;
  f.uz = zb - za;
  f.a = f.uy * f.uy + f.uz * f.uz;
  if (!(f.a > 0.0)) return 0.0;
  f.len_m = std::sqrt(f.a);
  f.inv_a = 1.0 / f.a;
  const double wy = ya, wz = za - hs;  // w = A - S
  f.tm0 = -(wy * f.uy + wz * f.uz) / f.a;
  const double cross = wy * f.uz - wz * f.uy;
  const double c0 = cross / f.len_m;  // cos(incidence) r, > 0 iff the facet faces the sensor
  f.p2 = cross * cross / f.a;
  f.cross = cross;
  f.w2 = wy * wy + wz * wz;
  f.wu = wy * f.uy + wz * f.uz;
  f.theta_a = std::atan2(-wz, wy);
  f.az_rel = wz;
  f.theta_off = f.theta_a - in.axis_rad;
  f.set_series_terms();
  f.index = index;
  f.coef = coef_per_c0sq * c0 * c0;
  f.glint_coef = 0.0;
  f.max_piece_over_range = kMaxPieceOverRange;
  return c0;
}

// Adds the glint `lobe` of the facet's material to a facet set up by setup_facet (c0 its return
// value, kb = K beta_eff): its pieces are then at most s / 4 of their range long, so that the
// Gauss rule resolves the lobe (width s in tan theta).
inline void add_glint(Facet& f, double c0, double kb, const KirchhoffLobe& lobe) {
  if (!(lobe.peak > 0.0) || !(c0 > 0.0)) return;
  f.lobe = lobe;
  f.glint_coef = kb * c0 * c0;
  f.inv_c02 = 1.0 / (c0 * c0);
  const double quarter_s = 0.25 / std::sqrt(2.0 * lobe.inv_2s2);
  f.max_piece_over_range = std::min(kMaxPieceOverRange, quarter_s);
}

}  // namespace sonarsynth::render_facet
