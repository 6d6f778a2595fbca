// SPDX-License-Identifier: MIT
#include "sonarsynth/render_side.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/render_facet.hpp"
#include "sonarsynth/render_gather.hpp"
#include "sonarsynth/render_math.hpp"
#include "sonarsynth/render_sections.hpp"
#include "sonarsynth/simd.hpp"

namespace sonarsynth {
namespace {

using namespace render_math;
using namespace render_facet;
using render_gather::gather;

constexpr double kInf = std::numeric_limits<double>::infinity();
// y used in tan(depression) = (Hs - z) / y at nadir (docs/physics.md Appendix A: y_A = eps).
constexpr double kMinTanY = 1e-9;

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

using HorizonStep = SideEcho::Workspace::HorizonStep;

// The label of the occluder `o`: a seabed piece's facet label (0, or an object entered in the
// height profile) or its section's object id.
inline std::int32_t occluder_label(const BeamProfile& prof, const Segment& o) {
  return static_cast<std::size_t>(o.facet) < prof.seabed_facets()
             ? prof.label[static_cast<std::size_t>(o.facet)]
             : prof.section_label[o.section];
}

// Records that the objects' horizon in the height profile (the running minimum of
// tan(depression) over its facets with a label > 0) came down to `tan` through a facet labelled
// `label`.
inline void add_horizon_step(std::vector<HorizonStep>& steps, double tan, std::int32_t label) {
  if (!steps.empty() && steps.back().label == label) {
    steps.back().tan = tan;
  } else {
    steps.push_back({tan, label});
  }
}

// Marks the part [h0, h1] of the height-profile facet A -> B (absolute heights, sensor at
// height hs) that the horizon hides, each point with the label of the nearest object of the
// profile that its ray from the sensor passes through (the first step of `steps` below the
// point's tan(depression)), 0 where none does (seabed relief alone hides it). tan is monotone
// along a straight facet, so the part splits into one piece per step it spans.
template <class Grid>
void mark_horizon_shadow(const Facet& f, const Grid& grid, double hs, double ya, double za,
                         double yb, double zb, double h0, double h1,
                         const std::vector<HorizonStep>& steps, std::vector<std::int32_t>& caster) {
  if (!(h1 > h0)) return;
  const double uy = yb - ya, uz = zb - za;
  // Index of the first step below the tan at t; steps.size() if none (relief).
  const auto step_of = [&](double t) {
    const double tp = tan_depression(ya + t * uy, za - hs + t * uz);
    return static_cast<std::size_t>(
        std::partition_point(steps.begin(), steps.end(),
                             [tp](const HorizonStep& s) { return s.tan >= tp; }) -
        steps.begin());
  };
  const auto label = [&](std::size_t k) { return k < steps.size() ? steps[k].label : 0; };
  const std::size_t k0 = step_of(h0), k1 = step_of(h1);
  std::size_t k = k0;
  double from = h0;
  while (k != k1) {
    const std::size_t next = k0 < k1 ? k + 1 : k - 1;
    // The boundary between steps k and next: the tan the nearer of them came down to.
    const double tb = steps[std::min(k, next)].tan;
    const double den = uz + tb * uy;
    double t = den != 0.0 ? (hs - za - tb * ya) / den : from;
    t = std::isnan(t) ? from : std::clamp(t, from, h1);
    mark_shadow(f, grid, from, t, label(k), caster);
    from = t;
    k = next;
  }
  mark_shadow(f, grid, from, h1, label(k), caster);
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
    const Material& mat = par.materials[prof.section_facet_mat(
        s.section, static_cast<std::size_t>(s.facet) - prof.seabed_facets())];
    const double c0 = setup_facet(f, in, hs, s.y0, s.z0 + hs, s.y1, s.z1 + hs, s.facet,
                                  kb * backscatter_coefficient(par.backscatter, mat));
    if (!(f.a > 0.0) || !(c0 > 0.0)) continue;
    if (par.object_glints && mat.specular_rho > 0.0)
      add_glint(f, c0, kb, specular_lobe(par.backscatter, mat));
    auto& vis = w.visible;
    vis.assign({0.0, 1.0});
    if (par.shadows) {
      const double uy = s.y1 - s.y0, uz = s.z1 - s.z0;
      const auto hide = [&](const Segment& o) {
        double q0 = 0.0, q1 = 0.0;
        if (!hidden_by(o, s.y0, s.z0, uy, uz, q0, q1) || !(q1 - q0 > kMinHidden)) return;
        subtract_interval(vis, w.visible_next, q0, q1);
        if constexpr (kTruth)
          mark_shadow(f, grid, q0, q1, occluder_label(prof, o), w.shadow_caster);
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

// The integrand's constants of a side (render_facet::Integrand); the beam's kinks in
// kink_storage or its table.
inline Integrand make_integrand(const BeamProfile& prof, const SideParams& par,
                                double (&kink_storage)[3]) {
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
               kInf,
               shape == VerticalBeamShape::paper_sine_pair,
               par.vertical_beam.upper_half_width_rad,
               par.vertical_beam.lower_half_width_rad};
  if (in.beam != nullptr) in.kinks = beam_kinks(par.vertical_beam, kink_storage);
  if (shape == VerticalBeamShape::paper_sine_pair) {
    in.lit_lo = -par.vertical_beam.upper_half_width_rad;
    in.lit_hi = par.vertical_beam.lower_half_width_rad;
  }
  return in;
}

// The vector kernel's arguments for the beams it evaluates (render_facet::Workspace::kernel).
template <class Grid>
render_kernel::PieceArgs piece_args(const Grid& grid, const Integrand& in) {
  render_kernel::PieceArgs kernel{};
  kernel.dr = grid.dr;
  kernel.split_f = split_width(grid);
  kernel.axis_rad = in.axis_rad;
  kernel.gauss_coef = in.gauss_coef;
  kernel.kappa_per_m = in.kappa_per_m;
  kernel.spreading = in.spreading;
  kernel.paper = in.paper;
  kernel.paper_upper_rad = in.paper_upper_rad;
  kernel.paper_lower_rad = in.paper_lower_rad;
  kernel.gauss_points = in.rule->n;
  kernel.gauss_x = in.rule->x;
  kernel.gauss_w = in.rule->w;
  return kernel;
}

// The tan(depression) range of the closed sections' occluders and their widest tan span.
struct SectionRange {
  double tan_lo = kInf, tan_hi = -kInf, span = 0.0;
  bool meets(double lo, double hi) const { return hi >= tan_lo && lo <= tan_hi; }
};

// The closed sections' front facets (objects off the seabed, BeamProfile) as occluders of the
// seabed and of each other (w.occluders, and w.occluders_by_tan by increasing tan_lo); clears
// the seabed pieces kept to occlude them.
inline SectionRange prepare_occluders(const BeamProfile& prof, SideEcho::Workspace& w) {
  section_occluders(prof, kMinTanY, w.occluders);
  w.seabed_pieces.clear();
  SectionRange r;
  for (const Segment& o : w.occluders) {
    r.tan_lo = std::min(r.tan_lo, o.tan_lo);
    r.tan_hi = std::max(r.tan_hi, o.tan_hi);
    r.span = std::max(r.span, o.tan_hi - o.tan_lo);
  }
  auto& by_tan = w.occluders_by_tan;
  by_tan.assign(w.occluders.begin(), w.occluders.end());
  std::sort(by_tan.begin(), by_tan.end(),
            [](const Segment& a, const Segment& b) { return a.tan_lo < b.tan_lo; });
  return r;
}

// Horizon sweep with exact clipping (docs/physics.md §2.1 step 3, Appendix A) of the facet
// A -> B (tan(depression) ta, tb at its ends) against the horizon tan_h: its visible part
// [t0, t1] and hidden part [h0, h1] (t0 = 0, t1 = 1, h0 = h1 = 0 on entry).
[[gnu::always_inline]] inline void clip_to_horizon(double hs, double ya, double za, double yb,
                                                   double zb, double ta, double tb, double tan_h,
                                                   double& t0, double& t1, double& h0, double& h1) {
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
}

// The part [t0, t1] of the seabed facet (ya, wz) + t (uy, uz) (relative to the sensor) as a
// piece that occludes the sections.
[[gnu::always_inline]] inline Segment seabed_piece(double ya, double wz, double uy, double uz,
                                                   double t0, double t1, std::size_t facet) {
  const double ya0 = ya + t0 * uy, za0 = wz + t0 * uz, ya1 = ya + t1 * uy, za1 = wz + t1 * uz;
  const double tp0 = tan_depression(ya0, za0), tp1 = tan_depression(ya1, za1);
  return {ya0,
          za0,
          ya1,
          za1,
          std::min(tp0, tp1),
          std::max(tp0, tp1),
          0,
          static_cast<std::int32_t>(facet)};
}

// Truth: a closed section on the ray of a point of the hidden part [h0, h1] of facet f (from
// (ya, za)) also casts it: its label wins over relief (mark_shadow keeps the largest).
template <class Grid>
[[gnu::always_inline]] inline void mark_section_shadows(const BeamProfile& prof, const Grid& grid,
                                                        const SectionRange& sec, const Facet& f,
                                                        double ya, double za, double h0, double h1,
                                                        SideEcho::Workspace& w) {
  const double wz = za - prof.sensor_z_m, uy = f.uy, uz = f.uz;
  const double tp0 = tan_depression(ya + h0 * uy, wz + h0 * uz);
  const double tp1 = tan_depression(ya + h1 * uy, wz + h1 * uz);
  const double tlo = std::min(tp0, tp1), thi = std::max(tp0, tp1);
  if (!sec.meets(tlo, thi)) return;
  for (const Segment& o : occluders_meeting(w.occluders_by_tan, sec.span, tlo, thi)) {
    if (o.tan_hi < tlo || o.tan_lo > thi) continue;
    double q0 = 0.0, q1 = 0.0;
    if (!hidden_by(o, ya, wz, uy, uz, q0, q1)) continue;
    mark_shadow(f, grid, std::max(q0, h0), std::min(q1, h1), prof.section_label[o.section],
                w.shadow_caster);
  }
}

// Renders the lit part [t0, t1] of seabed facet i (f, from (ya, za)); with sections that cast
// shadows, first keeps the part to occlude them, then removes what they hide.
template <bool kTruth, class Grid>
[[gnu::always_inline]] inline void render_lit_seabed(const BeamProfile& prof, const SideParams& par,
                                                     const Grid& grid, const Integrand& in,
                                                     const Workspace& ws, const SectionRange* sec,
                                                     std::size_t i, const Facet& f, double ya,
                                                     double za, double t0, double t1,
                                                     SideEcho::Workspace& w) {
  if (sec != nullptr && par.shadows) {
    const double wz = za - prof.sensor_z_m, uy = f.uy, uz = f.uz;
    const Segment piece = seabed_piece(ya, wz, uy, uz, t0, t1, i);
    const double tlo = piece.tan_lo, thi = piece.tan_hi;
    w.seabed_pieces.push_back(piece);
    if (sec->meets(tlo, thi)) {
      auto& vis = w.visible;
      vis.assign({t0, t1});
      for (const Segment& o : occluders_meeting(w.occluders_by_tan, sec->span, tlo, thi)) {
        if (o.tan_hi < tlo || o.tan_lo > thi) continue;
        double q0 = 0.0, q1 = 0.0;
        if (!hidden_by(o, ya, wz, uy, uz, q0, q1)) continue;
        q0 = std::max(q0, t0);
        q1 = std::min(q1, t1);
        if (!(q1 - q0 > kMinHidden)) continue;
        subtract_interval(vis, w.visible_next, q0, q1);
        if constexpr (kTruth)
          mark_shadow(f, grid, q0, q1, prof.section_label[o.section], w.shadow_caster);
      }
      for (std::size_t v = 0; v + 1 < vis.size(); v += 2) {
        render_lit<kTruth>(f, in, grid, vis[v], vis[v + 1], std::clamp(f.tm0, vis[v], vis[v + 1]),
                           ws);
      }
      return;
    }
  }
  render_lit<kTruth>(f, in, grid, t0, t1, std::clamp(f.tm0, t0, t1), ws);
}

template <bool kTruth, class Grid>
bool sweep(const BeamProfile& prof, const SideParams& par, const Grid& grid, SideEcho& out) {
  auto& w = out.workspace;
  double kink_storage[3];
  const Integrand in = make_integrand(prof, par, kink_storage);
  render_kernel::PieceArgs kernel = piece_args(grid, in);
  // The scalar target keeps the scalar gauss_sum: the reference the vector paths are tested
  // against (Highway's EMU128 copy of the kernel would be slower than it).
  const bool vector =
      (in.beam == nullptr || in.paper) && simd::active_target() != simd::Target::scalar;
  const Workspace ws{w.fine_energy.data(), w.best_energy.data(), w.best_facet.data(),
                     w.best_y_m.data(),    w.best_dz_m.data(),   vector ? &kernel : nullptr};
  const double hs = prof.sensor_z_m;
  const double r_max = grid.edge(grid.n);
  const double kb = par.calibration_k * par.beta_eff_rad;
  bool any_valid = false;
  double tan_h = kInf;                     // running minimum of tan(depression) (the horizon)
  [[maybe_unused]] double tan_obj = kInf;  // the same over the facets labelled > 0 (truth)
  if constexpr (kTruth) w.horizon_steps.clear();
  const std::size_t n = prof.nodes();
  // Closed sections (objects off the seabed, BeamProfile): their front facets occlude the
  // seabed and each other; visible seabed pieces facing the sensor are kept to occlude them.
  const SectionRange sec = prepare_occluders(prof, w);
  const bool has_sections = !w.occluders.empty();
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
      const double ta = (hs - za) / std::max(ya, kMinTanY);
      const double tb = (hs - zb) / std::max(yb, kMinTanY);
      clip_to_horizon(hs, ya, za, yb, zb, ta, tb, tan_h, t0, t1, h0, h1);
      if constexpr (kTruth) {
        if (prof.label[i] > 0 && std::min(ta, tb) < tan_obj) {
          tan_obj = std::min(ta, tb);
          add_horizon_step(w.horizon_steps, tan_obj, prof.label[i]);
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
      w.seabed_pieces.push_back(seabed_piece(ya, wz, uy, uz, t0, t1, i));
      continue;
    }
    const double c0 =
        setup_facet(f, in, hs, ya, za, yb, zb, static_cast<std::int32_t>(i),
                    kb * backscatter_coefficient(par.backscatter, par.materials[prof.material[i]]));
    if constexpr (kTruth) {
      mark_horizon_shadow(f, grid, hs, ya, za, yb, zb, h0, h1, w.horizon_steps, w.shadow_caster);
      if (has_sections && h1 > h0) mark_section_shadows(prof, grid, sec, f, ya, za, h0, h1, w);
    }
    // Lit part only; a facet seen from behind or edge-on (c0 <= 0) returns nothing.
    if (!(t1 > t0) || !(c0 > 0.0)) continue;
    render_lit_seabed<kTruth>(prof, par, grid, in, ws, has_sections ? &sec : nullptr, i, f, ya, za,
                              t0, t1, w);
  }
  if (has_sections) render_sections<kTruth>(prof, par, grid, in, kb, sec.span, ws, w);
  return any_valid || has_sections;
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
    w.shadow_caster.assign(nf, -1);
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
  simd::configure_from_environment();
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
