// SPDX-License-Identifier: MIT
#include "sonarsynth/render_side.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <span>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/render_math.hpp"
#include "sonarsynth/render_sections.hpp"

namespace sonarsynth {
namespace {

using namespace render_math;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
// y used in tan(depression) = (Hs - z) / y at nadir (docs/physics.md Appendix A: y_A = eps).
constexpr double kMinTanY = 1e-9;

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
};

// The kinks of a beam (Integrand::kinks), in `storage` (3 entries) or the table itself.
std::span<const double> beam_kinks(const VerticalBeamPattern& b, double (&storage)[3]) {
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
};

// Longest sub-piece integrated by one Gauss rule, relative to its distance from the sensor:
// the integrand varies on the scale of r, so the rule's error ~ (l / r)^4 (near nadir a bin spans
// metres of seabed). 0.02 keeps the 2-point rule below ~1e-9 relative on a flat seabed.
constexpr double kMaxPieceOverRange = 0.02;

#ifdef SONARSYNTH_GAUSS_PAIRS
// Two Gauss points (parameters t, weights w) of the integrand below in the lanes of one vector:
// the same operations as gauss_sum's scalar loop lane by lane. Requires r2 > 0 in both lanes
// (the caller checks), a Gaussian or uniform beam and, with a Gaussian beam, the atan series
// valid on the facet (series_terms > 0).
[[gnu::always_inline]] inline V2d gauss_pair(const Facet& f, const Integrand& in, V2d t, V2d w,
                                             V2d r2) {
  const V2d r = sqrt2(r2);
  V2d v = w / (in.spreading ? r2 * r2 * r : r);
  V2d expo = V2d{} + 0.0;
  if (in.gauss_coef > 0.0) {
    const V2d x = (t * f.cross) / (f.w2 + t * f.wu);
    const V2d off = f.theta_off - x * atan_poly(x * x, f.series_terms);
    expo -= in.gauss_coef * off * off;
  }
  if (in.kappa_per_m > 0.0) expo -= in.kappa_per_m * r;
  if (in.gauss_coef > 0.0 || in.kappa_per_m > 0.0) v *= exp_table2(expo);
  return v;
}
#endif

// Gauss–Legendre sum over [q0, q1] (in t) of the integrand without the arc-length factor.
[[gnu::always_inline]] inline double gauss_sum(const Facet& f, const Integrand& in, double q0,
                                               double dq) {
  const GaussRule& rule = *in.rule;
  double sum = 0.0;
  int g = 0;
#ifdef SONARSYNTH_GAUSS_PAIRS
  if (in.beam == nullptr && (f.series_terms > 0 || !(in.gauss_coef > 0.0))) {
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
    } else if (in.beam != nullptr) {
      v *= in.beam->two_way(f.depression(t, py, dz) - in.axis_rad);
    }
    if (in.kappa_per_m > 0.0) expo -= in.kappa_per_m * r;
    if (expo != 0.0) v *= exp_table(expo);
    sum += v;
  }
  return sum;
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
  double sum;
  if (dl * dl <= kMaxPieceOverRange * kMaxPieceOverRange * rmid2) {
    sum = gauss_sum(f, in, q0, dq);
  } else {
    const double parts = std::ceil(dl / (kMaxPieceOverRange * std::sqrt(rmid2)));
    const int n = static_cast<int>(std::min(parts, 4096.0));
    const double h = dq / static_cast<double>(n);
    sum = 0.0;
    for (int k = 0; k < n; ++k) sum += gauss_sum(f, in, q0 + static_cast<double>(k) * h, h);
    sum /= static_cast<double>(n);
  }
  const double e = sum * dl * f.coef;
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

// Marks the fine bins spanned by the hidden part [h0, h1] of a facet as shadow (truth only).
template <class Grid>
void mark_shadow(const Facet& f, const Grid& grid, double h0, double h1,
                 std::vector<std::uint8_t>& shadowed) {
  if (!(h1 > h0)) return;
  const double tm = std::clamp(f.tm0, h0, h1);
  const double ra = f.range(h0), rb = f.range(h1), rm = f.range(tm);
  const double lo = std::min({ra, rb, rm});
  const double hi = std::max({ra, rb, rm});
  if (lo >= grid.edge(grid.n)) return;
  const std::ptrdiff_t j0 = std::max<std::ptrdiff_t>(0, grid.index(lo));
  const std::ptrdiff_t j1 = std::min<std::ptrdiff_t>(grid.n - 1, grid.index(hi));
  for (std::ptrdiff_t j = j0; j <= j1; ++j) shadowed[static_cast<std::size_t>(j)] = 1;
}

using sections::hidden_by;
using sections::kMinHidden;

// The occluders (sorted by tan_lo, widest tan span `span`) whose tan range can meet [lo, hi]:
// those with tan_lo in [lo - span, hi] (a small margin below for the rounding of the span).
std::span<const sections::Segment> occluders_meeting(const std::vector<sections::Segment>& by_tan,
                                                     double span, double lo, double hi) {
  const double from = lo - 1.001 * span - 1e-12 * std::abs(lo);
  const auto a = std::partition_point(
      by_tan.begin(), by_tan.end(), [from](const sections::Segment& o) { return o.tan_lo < from; });
  const auto b = std::partition_point(a, by_tan.end(),
                                      [hi](const sections::Segment& o) { return o.tan_lo <= hi; });
  return {a, b};
}
using sections::section_occluders;
using sections::Segment;
using sections::subtract_interval;

// tan(depression) relative to the sensor, guarded at nadir as the horizon sweep is.
inline double tan_depression(double y_rel, double z_rel) {
  return sections::tan_depression(y_rel, z_rel, kMinTanY);
}

// The facet A -> B (absolute coordinates) of the integrand; returns c0 = cos(incidence) r (> 0
// iff it faces the sensor); f.a = 0 for a zero-length facet (then nothing else is set).
double setup_facet(Facet& f, const Integrand& in, double hs, double ya, double za, double yb,
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
  return c0;
}

// Renders the front facets of the closed sections (w.occluders), each minus what the seabed
// (w.seabed_pieces: the visible seabed facing the sensor, in order of decreasing tan(depression))
// and the other sections hide.
template <bool kTruth, class Grid>
void render_sections(const BeamProfile& prof, const SideParams& par, const Grid& grid,
                     const Integrand& in, double kb, double span, const Workspace& ws,
                     SideEcho::Workspace& w) {
  const double hs = prof.sensor_z_m;
  const auto& pieces = w.seabed_pieces;
  for (const Segment& s : w.occluders) {
    Facet f{};
    const double c0 = setup_facet(
        f, in, hs, s.y0, s.z0 + hs, s.y1, s.z1 + hs, s.facet,
        kb * backscatter_coefficient(
                 par.backscatter,
                 par.materials[prof.section_facet_mat(
                     s.section, static_cast<std::size_t>(s.facet) - prof.seabed_facets())]));
    if (!(f.a > 0.0) || !(c0 > 0.0)) continue;
    auto& vis = w.visible;
    vis.assign({0.0, 1.0});
    if (par.shadows) {
      const double uy = s.y1 - s.y0, uz = s.z1 - s.z0;
      const auto hide = [&](const Segment& o) {
        double q0 = 0.0, q1 = 0.0;
        if (!hidden_by(o, s.y0, s.z0, uy, uz, q0, q1) || !(q1 - q0 > kMinHidden)) return;
        subtract_interval(vis, w.visible_next, q0, q1);
        if constexpr (kTruth) mark_shadow(f, grid, q0, q1, w.shadowed);
      };
      // Seabed pieces whose tan range meets [tan_lo, tan_hi]: they are sorted by decreasing tan.
      auto it = std::partition_point(pieces.begin(), pieces.end(),
                                     [&](const Segment& p) { return p.tan_lo > s.tan_hi; });
      for (; it != pieces.end() && it->tan_hi >= s.tan_lo && vis.size() > 1; ++it) hide(*it);
      // Its own section too: a mesh's section need not be convex (docs/physics.md §2.1). The
      // visible part left does not depend on the order of the occluders (subtract_interval keeps
      // their ends as they are).
      for (const Segment& o : occluders_meeting(w.occluders_by_tan, span, s.tan_lo, s.tan_hi)) {
        if (o.facet == s.facet || o.tan_hi < s.tan_lo || o.tan_lo > s.tan_hi) continue;
        if (vis.size() < 2) break;
        hide(o);
      }
    }
    for (std::size_t v = 0; v + 1 < vis.size(); v += 2) {
      render_lit<kTruth>(f, in, grid, vis[v], vis[v + 1], std::clamp(f.tm0, vis[v], vis[v + 1]),
                         ws);
    }
  }
}

template <bool kTruth, class Grid>
bool sweep(const BeamProfile& prof, const SideParams& par, const Grid& grid, SideEcho& out) {
  auto& w = out.workspace;
  const Workspace ws{w.fine_energy.data(), w.best_energy.data(), w.best_facet.data(),
                     w.best_y_m.data(), w.best_dz_m.data()};
  const VerticalBeamShape shape = par.vertical_beam.shape;
  const double w3 = par.vertical_beam.width_3db_rad;
  // Two-way Gaussian: (exp(-4 ln2 (off/W)^2))^2 = exp(-8 ln2 off^2 / W^2), docs/physics.md §1.3.
  Integrand in{prof.sensor_z_m,
               par.beam_axis_depression_rad,
               (shape == VerticalBeamShape::uniform || shape == VerticalBeamShape::gaussian)
                   ? nullptr
                   : &par.vertical_beam,
               shape == VerticalBeamShape::gaussian ? 8.0 * std::log(2.0) / (w3 * w3) : 0.0,
               par.spreading,
               par.absorption_db_per_m * 2.0 * std::log(10.0) / 10.0,
               &kRules[par.gauss_points - 1],
               {},
               -kInf,
               kInf};
  double kink_storage[3];
  if (in.beam != nullptr) in.kinks = beam_kinks(par.vertical_beam, kink_storage);
  if (shape == VerticalBeamShape::paper_sine_pair) {
    in.lit_lo = -par.vertical_beam.upper_half_width_rad;
    in.lit_hi = par.vertical_beam.lower_half_width_rad;
  }
  const double hs = prof.sensor_z_m;
  const double r_max = grid.edge(grid.n);
  const double kb = par.calibration_k * par.beta_eff_rad;
  bool any_valid = false;
  double tan_h = kInf;  // running minimum of tan(depression) (the horizon)
  const std::size_t n = prof.nodes();
  // Closed sections (objects off the seabed, BeamProfile): their front facets occlude the
  // seabed and each other; visible seabed pieces facing the sensor are kept to occlude them.
  auto& occluders = w.occluders;
  section_occluders(prof, kMinTanY, occluders);
  const bool has_sections = !occluders.empty();
  w.seabed_pieces.clear();
  double sec_tan_lo = kInf, sec_tan_hi = -kInf, span = 0.0;
  for (const Segment& o : occluders) {
    sec_tan_lo = std::min(sec_tan_lo, o.tan_lo);
    sec_tan_hi = std::max(sec_tan_hi, o.tan_hi);
    span = std::max(span, o.tan_hi - o.tan_lo);
  }
  auto& by_tan = w.occluders_by_tan;
  by_tan.assign(occluders.begin(), occluders.end());
  std::sort(by_tan.begin(), by_tan.end(),
            [](const Segment& a, const Segment& b) { return a.tan_lo < b.tan_lo; });
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double ya = prof.y_m[i], za = prof.z_m[i];
    const double yb = prof.y_m[i + 1], zb = prof.z_m[i + 1];
    if (ya >= r_max) break;                          // r >= y: nothing further out can reach a bin
    if (std::isnan(za) || std::isnan(zb)) continue;  // hole: no return, horizon unchanged
    any_valid = true;
    Facet f{};
    f.a = (yb - ya) * (yb - ya) + (zb - za) * (zb - za);
    double t0 = 0.0, t1 = 1.0;  // visible part
    double h0 = 0.0, h1 = 0.0;  // hidden part (truth)
    if (par.shadows) {
      // Horizon sweep with exact clipping (docs/physics.md §2.1 step 3, Appendix A).
      const double ta = (hs - za) / std::max(ya, kMinTanY);
      const double tb = (hs - zb) / std::max(yb, kMinTanY);
      const bool va = ta <= tan_h, vb = tb <= tan_h;
      if (!va && !vb) {
        t1 = 0.0;
        h1 = 1.0;
      } else if (va != vb) {
        const double den = (zb - za) + tan_h * (yb - ya);
        double ts = den != 0.0 ? (hs - za - tan_h * ya) / den : (va ? 1.0 : 0.0);
        ts = std::isnan(ts) ? (va ? 1.0 : 0.0) : std::clamp(ts, 0.0, 1.0);
        if (va) {
          t1 = ts;
          h0 = ts;
          h1 = 1.0;
        } else {
          t0 = ts;
          h1 = ts;
        }
      }
      tan_h = std::min({tan_h, ta, tb});
    }
    if (!(f.a > 0.0)) continue;  // zero-length facet
    // A facet wholly nearer than render_from_m: horizon only (its slant range is largest at an
    // end, the range being convex along it); it can still occlude the sections below.
    const bool skip = par.render_from_m > 0.0 &&
                      std::max(ya * ya + (za - hs) * (za - hs), yb * yb + (zb - hs) * (zb - hs)) <
                          par.render_from_m * par.render_from_m;
    if (skip) {
      // Only the piece that occludes the sections, as below (setup_facet's uy, uz and sign of
      // c0), without the integrand.
      if (!(has_sections && par.shadows) || !(t1 > t0)) continue;
      const double uy = yb - ya, uz = zb - za, wz = za - hs;
      if (!((ya * uz - wz * uy) / std::sqrt(f.a) > 0.0)) continue;
      const double ya0 = ya + t0 * uy, za0 = wz + t0 * uz, ya1 = ya + t1 * uy, za1 = wz + t1 * uz;
      const double tp0 = tan_depression(ya0, za0), tp1 = tan_depression(ya1, za1);
      w.seabed_pieces.push_back({ya0, za0, ya1, za1, std::min(tp0, tp1), std::max(tp0, tp1), 0,
                                 static_cast<std::int32_t>(i)});
      continue;
    }
    const double c0 =
        setup_facet(f, in, hs, ya, za, yb, zb, static_cast<std::int32_t>(i),
                    kb * backscatter_coefficient(par.backscatter, par.materials[prof.material[i]]));
    if constexpr (kTruth) mark_shadow(f, grid, h0, h1, w.shadowed);
    // Lit part only; a facet seen from behind or edge-on (c0 <= 0) returns nothing.
    if (!(t1 > t0) || !(c0 > 0.0)) continue;
    if (has_sections && par.shadows) {
      // Keep the piece to occlude the sections, then remove what the sections hide.
      const double wz = za - hs, uy = f.uy, uz = f.uz;
      const double ya0 = ya + t0 * uy, za0 = wz + t0 * uz, ya1 = ya + t1 * uy, za1 = wz + t1 * uz;
      const double tp0 = tan_depression(ya0, za0), tp1 = tan_depression(ya1, za1);
      const double tlo = std::min(tp0, tp1), thi = std::max(tp0, tp1);
      w.seabed_pieces.push_back({ya0, za0, ya1, za1, tlo, thi, 0, static_cast<std::int32_t>(i)});
      if (thi >= sec_tan_lo && tlo <= sec_tan_hi) {
        auto& vis = w.visible;
        vis.assign({t0, t1});
        for (const Segment& o : occluders_meeting(by_tan, span, tlo, thi)) {
          if (o.tan_hi < tlo || o.tan_lo > thi) continue;
          double q0 = 0.0, q1 = 0.0;
          if (!hidden_by(o, ya, wz, uy, uz, q0, q1)) continue;
          q0 = std::max(q0, t0);
          q1 = std::min(q1, t1);
          if (!(q1 - q0 > kMinHidden)) continue;
          subtract_interval(vis, w.visible_next, q0, q1);
          if constexpr (kTruth) mark_shadow(f, grid, q0, q1, w.shadowed);
        }
        for (std::size_t v = 0; v + 1 < vis.size(); v += 2) {
          render_lit<kTruth>(f, in, grid, vis[v], vis[v + 1], std::clamp(f.tm0, vis[v], vis[v + 1]),
                             ws);
        }
        continue;
      }
    }
    render_lit<kTruth>(f, in, grid, t0, t1, std::clamp(f.tm0, t0, t1), ws);
  }
  if (has_sections) render_sections<kTruth>(prof, par, grid, in, kb, span, ws, w);
  return any_valid || has_sections;
}

// Sample i <- fine bins [first(i), last(i)] (clipped at 0).
template <bool kTruth, class Window>
void gather(const BeamProfile& prof, const SideParams& par, bool any_valid, Window window,
            SideEcho& out) {
  auto& w = out.workspace;
  const std::size_t ns = par.samples;
  const std::ptrdiff_t nf = static_cast<std::ptrdiff_t>(w.fine_energy.size());
  std::ptrdiff_t first_return = nf;
  if constexpr (kTruth) {
    // The first seabed return: a target in mid-water (a section) has water column behind it.
    const auto seabed_facets = static_cast<std::int32_t>(prof.seabed_facets());
    for (std::ptrdiff_t j = 0; j < nf; ++j) {
      const auto u = static_cast<std::size_t>(j);
      if (w.fine_energy[u] > 0.0 && (prof.sections() == 0 || w.best_facet[u] < seabed_facets)) {
        first_return = j;
        break;
      }
    }
  }
  const bool grazing = par.truth_grazing;
  std::int32_t facet = -1;  // facet of the cached slope, label and material
  // Grazing angle without asin per sample: with the depression theta of the midpoint
  // (atan2(-mz, my)) and the facet's slope angle alpha = atan2(uz, uy), cos(incidence) =
  // -n.(my, mz) / r = sin(theta + alpha) for the upward unit normal n, so asin(clamp(cos_inc,
  // 0, 1)) = theta + alpha folded into [0, pi/2]. theta = theta_ref + atan(x) from a reference
  // midpoint (x = tan of the angle between the two rays, truncated series of
  // render_math where |x| < 0.1), atan2 otherwise (which becomes the new reference). The
  // reference is any earlier midpoint, of this facet or another.
  double alpha = 0.0;
  bool have_ref = false;
  double ref_y = 0.0, ref_z = 0.0, ref_theta = 0.0;
  std::int32_t label = 0;
  std::uint16_t material = 0;
  for (std::size_t i = 0; i < ns; ++i) {
    const auto [j0, j1] = window(static_cast<std::ptrdiff_t>(i));
    double sum = 0.0;
    std::ptrdiff_t jbest = -1;
    bool shadow = false;
    for (std::ptrdiff_t j = std::max<std::ptrdiff_t>(0, j0); j <= j1; ++j) {
      const auto u = static_cast<std::size_t>(j);
      sum += w.fine_energy[u];
      if constexpr (kTruth) {
        if (w.best_energy[u] > 0.0 &&
            (jbest < 0 || w.best_energy[u] > w.best_energy[static_cast<std::size_t>(jbest)])) {
          jbest = j;
        }
        shadow = shadow || w.shadowed[u] != 0;
      }
    }
    out.intensity[i] = sum;
    if constexpr (kTruth) {
      if (jbest >= 0) {
        // The dominant sub-piece's midpoint (my, mz) relative to the sensor; the normal of its
        // facet is computed once per run of samples sharing the facet.
        const auto b = static_cast<std::size_t>(jbest);
        const std::int32_t fi = w.best_facet[b];
        if (fi != facet) {
          facet = fi;
          const auto k = static_cast<std::size_t>(fi);
          if (grazing) {
            double ya, za, yb, zb;
            prof.facet_ends(k, ya, za, yb, zb);
            // Seabed facets are mostly flat to a tenth: the series there, atan2 otherwise.
            const double uy = yb - ya, uz = zb - za;
            if (uy > 0.0 && std::abs(uz) < 0.1 * uy) {
              const double x = uz / uy;
              alpha = x * atan_poly(x * x, 8);  // |x|^17 / 17 < 6e-19
            } else {
              alpha = std::atan2(uz, uy);
            }
          }
          label = prof.facet_label(k);
          material = prof.facet_material(k);
        }
        const double my = w.best_y_m[b], mz = w.best_dz_m[b];
        out.truth_class[i] = label > 0 ? SampleClass::object : SampleClass::seabed;
        out.truth_label[i] = label;
        out.truth_material[i] = material;
        if (grazing) {
          double g = 0.0;
          if (my * my + mz * mz > 0.0) {
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
            g = theta + alpha;  // in (-2 pi, 2 pi]: reduce to (-pi, pi], then fold
            if (g > std::numbers::pi) g -= 2.0 * std::numbers::pi;
            if (g <= -std::numbers::pi) g += 2.0 * std::numbers::pi;
            if (g > 0.5 * std::numbers::pi) g = std::numbers::pi - g;
            g = std::max(g, 0.0);
          }
          out.truth_grazing_rad[i] = g;
        }
        out.truth_ground_y_m[i] = my;
        out.truth_ground_z_m[i] = mz + prof.sensor_z_m;
      } else {
        out.truth_class[i] = shadow                             ? SampleClass::shadow
                             : (j1 < first_return && any_valid) ? SampleClass::water_column
                                                                : SampleClass::no_seabed;
        out.truth_label[i] = -1;
        out.truth_material[i] = 0;
        if (grazing) out.truth_grazing_rad[i] = kNaN;
        out.truth_ground_y_m[i] = kNaN;
        out.truth_ground_z_m[i] = kNaN;
      }
    }
  }
}

template <bool kTruth>
void render_impl(const BeamProfile& prof, const SideParams& par, SideEcho& out) {
  const double dr = par.sample_spacing_m;
  const auto ns = static_cast<std::ptrdiff_t>(par.samples);
  // Pulse window w = m dr + f.
  double m_real = std::floor(par.pulse_window_m / dr);
  double f = par.pulse_window_m - m_real * dr;
  if (f <= 1e-9 * dr) f = 0.0;
  if (dr - f <= 1e-9 * dr) {
    f = 0.0;
    m_real += 1.0;
  }
  const auto m = static_cast<std::ptrdiff_t>(m_real);
  const bool split = par.pulse_window_m > 0.0 && f > 0.0;
  const std::size_t nf = static_cast<std::size_t>(split ? 2 * ns : ns);
  auto& w = out.workspace;
  w.fine_energy.assign(nf, 0.0);
  if constexpr (kTruth) {
    w.best_energy.assign(nf, 0.0);
    w.best_facet.resize(nf);
    w.best_y_m.resize(nf);
    w.best_dz_m.resize(nf);
    w.shadowed.assign(nf, 0);
    out.truth_class.resize(par.samples);
    out.truth_label.resize(par.samples);
    out.truth_material.resize(par.samples);
    if (par.truth_grazing) {
      out.truth_grazing_rad.resize(par.samples);
    } else {
      out.truth_grazing_rad.clear();
    }
    out.truth_ground_y_m.resize(par.samples);
    out.truth_ground_z_m.resize(par.samples);
  }
  out.intensity.resize(par.samples);
  if (split) {
    const SplitGrid grid{dr, 1.0 / dr, f, 2 * ns};
    const bool any = sweep<kTruth>(prof, par, grid, out);
    gather<kTruth>(
        prof, par, any,
        [m](std::ptrdiff_t i) {
          return std::pair<std::ptrdiff_t, std::ptrdiff_t>{2 * (i - m) + 1, 2 * i + 1};
        },
        out);
  } else {
    const UniformGrid grid{dr, 1.0 / dr, ns};
    const bool any = sweep<kTruth>(prof, par, grid, out);
    const std::ptrdiff_t back = par.pulse_window_m > 0.0 ? m - 1 : 0;
    gather<kTruth>(
        prof, par, any,
        [back](std::ptrdiff_t i) {
          return std::pair<std::ptrdiff_t, std::ptrdiff_t>{i - back, i};
        },
        out);
  }
}

}  // namespace

void render_side(const BeamProfile& profile, const SideParams& params, SideEcho& out) {
  params.validate();
  validate_beam_profile(profile, params.materials.size(), "render_side");
  if (params.truth) {
    render_impl<true>(profile, params, out);
  } else {
    render_impl<false>(profile, params, out);
    out.clear_truth();
  }
}

}  // namespace sonarsynth
