// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sonarsynth/backscatter.hpp"
#include "sonarsynth/beam_pattern.hpp"
#include "sonarsynth/beam_profile.hpp"
#include "sonarsynth/rendered_ping.hpp"

namespace sonarsynth {

/// Parameters of the per-side renderer (docs/physics.md §1, §2.1, Appendix A).
/// Sample i covers the slant-range bin [i dr, (i + 1) dr) (dr = sample_spacing_m) or, with a
/// pulse window w > 0, the interval [(i + 1) dr - w, (i + 1) dr] (rectangular CW pulse, §1.4).
struct SideParams {
  double sample_spacing_m = 0.05;  ///< dr = c dt / 2, slant range per sample, metres, > 0
  std::size_t samples = 2000;      ///< samples per side, [1, 2^24]
  int gauss_points = 2;            ///< Gauss–Legendre points per sub-piece, [1, 5]
  bool shadows = true;             ///< horizon occlusion on (off: every facet is lit)
  /// Effective along-track beam width beta_eff, radians, (0, pi]: the ensonified strip at range
  /// r is r beta_eff wide (2-D beam-plane model, §1.3; see beta_eff_uniform_line_array_rad).
  double beta_eff_rad = 0.0174532925199433;  // 1 deg
  /// Vertical beam (one-way intensity, weighted two-way = squared).
  VerticalBeamPattern vertical_beam;
  /// Depression of the vertical beam axis below the horizontal in the beam plane, radians,
  /// [-pi, pi] (tilt; the caller adds the roll towards this side).
  double beam_axis_depression_rad = 0.349065850398866;  // 20 deg
  BackscatterModel backscatter = BackscatterModel::lambert;
  /// Object glints (docs/physics.md §1.11): the facets of closed sections whose material has a
  /// specular_rho > 0 add its Kirchhoff lobe (KirchhoffLobe) to the material's backscatter law.
  /// Off (the default here; the Simulator takes PhysicsConfig::object_glints): the law alone.
  bool object_glints = false;
  /// Material table indexed by BeamProfile::material; non-empty.
  std::vector<Material> materials = {Material{.name = "default"}};
  bool spreading = true;             ///< two-way spherical spreading r^-4 (off: factor 1)
  double absorption_db_per_m = 0.0;  ///< one-way alpha, dB/m, >= 0 (0 = off)
  double calibration_k = 1.0;        ///< global calibration constant K, linear, > 0
  double pulse_window_m = 0.0;       ///< c tau / 2, metres, >= 0 (0 = the sample bin itself)
  bool truth = false;                ///< fill SideEcho truth arrays
  /// With truth: also fill truth_grazing_rad (one asin per sample); false leaves it empty (the
  /// other truth arrays, e.g. for speckle keys and texture, are still filled).
  bool truth_grazing = true;
  /// Slant range, metres, >= 0, below which seabed facets are swept for the horizon (they still
  /// shadow what lies behind them) but not integrated: a facet whose slant range stays below it
  /// adds nothing. Bins that only such facets reach are then 0; every fine bin whose lower edge
  /// is at or above it is bit-identical to the render with 0 (the default: everything).
  double render_from_m = 0.0;

  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// Output of render_side for one side of one ping. All vectors are resized to
/// SideParams::samples; reuse one instance across pings to avoid allocation.
struct SideEcho {
  std::vector<double> intensity;  ///< linear received intensity per sample, >= 0

  // Truth (filled only with SideParams::truth; sized 0 otherwise). Describes the single
  // sub-piece of seabed contributing the most energy to the sample (its midpoint).
  std::vector<SampleClass> truth_class;
  /// Facet label (0 seabed, > 0 object id) of an echo; of a shadow sample the label of what hides
  /// it (0 seabed relief, > 0 the object id, docs/labels.md); -1 none.
  std::vector<std::int32_t> truth_label;
  std::vector<std::uint16_t> truth_material;  ///< facet material (0 if none)
  /// Grazing angle at the contributor, rad, NaN if none (empty unless SideParams::truth_grazing).
  std::vector<double> truth_grazing_rad;
  std::vector<double> truth_ground_y_m;  ///< beam-plane y of the contributor, m, NaN if none
  std::vector<double> truth_ground_z_m;  ///< height z of the contributor, m, NaN if none
  /// Empties every truth vector (keeping their capacity).
  void clear_truth() {
    truth_class.clear();
    truth_label.clear();
    truth_material.clear();
    truth_grazing_rad.clear();
    truth_ground_y_m.clear();
    truth_ground_z_m.clear();
  }

  /// Scratch space of the renderer (fine bins, per-bin dominance); not an output. Per fine bin
  /// the dominant sub-piece is recorded as its profile facet and midpoint only; its grazing
  /// angle, label and material are derived once per sample when gathering.
  struct Workspace {
    std::vector<double> fine_energy;
    std::vector<double> best_energy;
    std::vector<std::int32_t> best_facet;  ///< profile facet index of the dominant sub-piece
    std::vector<double> best_y_m;          ///< its midpoint's y
    std::vector<double> best_dz_m;         ///< its midpoint's z minus the sensor height
    /// Per fine bin: -1 if no hidden part falls there, else the label of what hides it (the
    /// largest if several: 0 seabed relief, > 0 object id; docs/labels.md).
    std::vector<std::int32_t> shadow_caster;
    /// The objects' horizon in the height profile (truth only): the running minimum of
    /// tan(depression) over its facets with a label > 0, as steps, nearest first (tan
    /// decreasing): each the tan it came down to and the label of the facets that brought it
    /// there, consecutive equal labels merged.
    struct HorizonStep {
      double tan;
      std::int32_t label;
    };
    std::vector<HorizonStep> horizon_steps;
    // Closed sections (BeamProfile sections): their front-facing facets, the seabed pieces that
    // can occlude them, and visible-interval lists (flattened pairs of facet parameters).
    struct Segment {
      double y0, z0, y1, z1;  ///< end points relative to the sensor, cross(P0, P1) > 0
      double tan_lo, tan_hi;  ///< range of tan(depression) it spans
      std::uint32_t section;  ///< section index (occluders) or 0
      std::int32_t facet;     ///< facet index (BeamProfile::facet_ends)
    };
    std::vector<Segment> occluders;
    std::vector<Segment> occluders_by_tan;  ///< the occluders by increasing tan_lo
    std::vector<Segment> seabed_pieces;
    std::vector<double> visible, visible_next;
    /// Per sample: the contributor's z minus the sensor height (the vector grazing angles).
    std::vector<double> sample_dz_m;
  } workspace;
};

/// Checks what every renderer of a beam-plane profile relies on: z_m, label and material sizes
/// agree with y_m, y_m finite and non-decreasing from 0, sensor_z_m finite, material indices below
/// `material_count`. Throws InputError("<who>: ...") naming the field and value.
void validate_beam_profile(const BeamProfile& profile, std::size_t material_count, const char* who);

/// Renders one side of one ping: exact horizon sweep with facet clipping, split of every facet
/// at its slant-range minimum and at every bin boundary (quadratic roots), Gauss–Legendre
/// integration in arc length of
///   K sigma_b(phi) b^2(theta - theta_axis) beta_eff r r^-4 10^(-2 alpha r / 10) dl
/// on each sub-piece, contributions SUMMED per bin (docs/physics.md Appendix A). No per-ping
/// normalisation. Throws InputError if params or the profile are invalid (sizes, y order,
/// material index).
void render_side(const BeamProfile& profile, const SideParams& params, SideEcho& out);

}  // namespace sonarsynth
