// SPDX-License-Identifier: MIT
// The scene file's bounds on a dataset spec (docs/dataset.md, "Validation"): the range of each
// key the scene file bounds, and the constraints that tie several keys together, checked on the
// extremes of the spec's ranges so that no drawn item fails them.
#include <algorithm>
#include <cmath>
#include <string_view>

#include "sonarsynth/bathy_gen.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/bathy_spec_parser.hpp"
#include "sonarsynth/formats/config/dataset_spec_parts.hpp"
#include "sonarsynth/formats/config/option_table.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"  // RunLimits
#include "sonarsynth/object_types.hpp"
#include "sonarsynth/sonar_presets.hpp"

namespace sonarsynth::dataset_spec {
namespace {

// What a scene file accepts for one key (docs/scene-format.md), from the declarations its reader
// uses: the option table (formats/config/option_table.cpp) and the bathymetry generators'
// parameters (formats/config/bathy_spec_parser.cpp) and the object table
// (include/sonarsynth/object_types.hpp). The keys of a `materials` entry are bounded in the scene
// reader's code (formats/config/scene_file.cpp); their bounds are restated here.
struct SceneBound {
  std::string key;
  double lo = -kInf, hi = kInf;
  bool lo_open = false, hi_open = false;
  bool accepts(double v) const {
    return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  std::string constraint() const {
    std::string c = key;
    if (std::isfinite(lo)) c += (lo_open ? " > " : " >= ") + number_text(lo);
    if (std::isfinite(hi)) {
      c += std::string(std::isfinite(lo) ? " and" : "") + (hi_open ? " < " : " <= ") +
           number_text(hi);
    }
    return c;
  }
};

SceneBound scene_bound(std::string_view scene_key) {
  const std::string key(scene_key);
  const auto from_param = [&](const bathy_spec::Param& p) {
    return SceneBound{key, p.lo, p.hi, p.lo_open, p.hi_open};
  };
  constexpr std::string_view kComponents = "bathymetry.generate.components.";
  if (scene_key.starts_with(kComponents)) {
    const std::string_view rest = scene_key.substr(kComponents.size());
    const std::size_t dot = rest.find('.');
    if (const auto* c = bathy_spec::find_component(rest.substr(0, dot))) {
      for (const bathy_spec::Param& p : c->params) {
        if (p.key == rest.substr(dot + 1)) return from_param(p);
      }
    }
  } else if (scene_key == "bathymetry.generate.depth_m") {
    return from_param(bathy_spec::depth_param());
  } else if (scene_key == "materials.texture_shape") {
    return {key, 0.0, 1e6};
  } else if (scene_key == "materials.reflectivity") {
    return {key, 0.0, 1.0};
  } else if (scene_key == "objects.scale") {
    const ObjectParam& p = *find_object_type("mesh")->param("scale");
    return {key, p.lo, p.hi, p.lo_open, false};
  } else {
    const options::Option& o = options::at(scene_key);
    return {key, o.lo, o.hi, o.lo_open, false};
  }
  throw std::logic_error("dataset spec: no scene key " + key);
}

}  // namespace

// Every value of `r` as the item's scene file will hold it (rounded to `decimals`) must be one
// that the scene file accepts for `scene_key`.
void check_scene_bound(const Fields& f, const std::string& key, NumberRange r, int decimals,
                       std::string_view scene_key) {
  const SceneBound b = scene_bound(scene_key);
  if (!b.accepts(rounded(r.lo, decimals)) || !b.accepts(rounded(r.hi, decimals))) {
    f.fail_value(key, b.constraint() + " in the item's scene file (docs/scene-format.md), " +
                          "every value as written there (to " + std::to_string(decimals) +
                          " decimals)");
  }
}

// A range of a key the scene file bounds: a number or [lo, hi] within `scene_key`'s bounds.
NumberRange read_scene_range(const Fields& f, const std::string& key, NumberRange fallback,
                             std::string_view scene_key, int decimals) {
  const NumberRange r = read_range(f, key, fallback, -kInf, kInf);
  if (f.given(key)) check_scene_bound(f, key, r, decimals, scene_key);
  return r;
}

// Largest horizontal distance of a point of an object from its position, metres.
double max_object_extent_m(const DatasetSpec& s) {
  double e = 0.0;
  for (const DatasetObjectType& t : s.object_types) {
    switch (find_object_type(t.type)->shape) {
      case ObjectShape::kEllipsoid:  // rock, moored sphere
        e = std::max(e, t.diameter_m.hi);
        break;
      case ObjectShape::kCylinder:  // pipe
        e = std::max(e, t.length_m.hi / 2.0 + t.diameter_m.hi);
        break;
      case ObjectShape::kBox:
        e = std::max(e, std::hypot(t.length_m.hi, t.width_m.hi) / 2.0);
        break;
      case ObjectShape::kMesh:
        e = std::max(e, t.model_radius_m * t.scale.hi);
        break;
    }
  }
  return e;
}

// The side of an item's square grid: it holds the line and its swath whatever the heading, with
// a margin for the largest object.
double grid_side_m(const DatasetSpec& s, double max_range_m) {
  const double half_m = s.line_length_m / 2.0 + std::max(max_range_m, s.across_track_m.hi) +
                        max_object_extent_m(s) + 10.0;
  return 2.0 * std::ceil(half_m / s.cell_m) * s.cell_m;
}

// The constraints of the scene file that tie several keys together (docs/scene-format.md,
// "Checks before the run"), checked on the extremes of the spec's ranges so that no drawn item
// fails them. The seabed's relief under the line and the sensor's motion are bounded as
// docs/dataset.md states ("Validation").
void check_item_constraints(const DatasetSpec& s) {
  const auto fail = [&](const std::string& key, const std::string& value,
                        const std::string& constraint) {
    throw InputError(s.file + ": " + key + " = '" + value +
                     "'. Violated constraint: " + constraint);
  };
  // The presets an item may draw, with the spec's range.
  double min_range_m = kInf, max_range_m = 0.0, max_pings = 0.0;
  const double line_m = s.line_length_m, slowest_m_s = rounded(s.speed_m_s.lo, 3);
  for (const std::string& name : s.sonar_preset.names) {
    SonarConfig c = find_sonar_preset(name)->sonar;
    const double preset_range_m = c.max_range_m;
    c.max_range_m = s.range_m ? rounded(s.range_m->lo, 3) : preset_range_m;
    min_range_m = std::min(min_range_m, c.max_range_m);
    max_range_m = std::max(max_range_m, s.range_m ? s.range_m->hi : preset_range_m);
    max_pings =
        std::max(max_pings, std::floor(line_m / (slowest_m_s * c.effective_ping_period_s())) + 1.0);
  }
  // The generator's size limit on an item's grid.
  const double side_m = grid_side_m(s, max_range_m);
  BathyGenSpec g;
  try {
    g.geometry = BathyGenSpec::centred_geometry(0.0, 0.0, side_m, side_m, s.cell_m);
  } catch (const InputError& e) {
    fail("seabed.cell_m", number_text(s.cell_m),
         std::string(e.what()) + " (an item's grid is " + number_text(side_m) +
             " m across: the line, the swath and the largest object)");
  }
  const RunLimits limits;
  if (!(max_pings <= static_cast<double>(limits.max_pings))) {
    fail("survey.speed_m_s", range_text(s.speed_m_s),
         "an item's line of " + number_text(line_m) +
             " m at the lowest speed and the shortest "
             "range (one ping per two-way travel time) takes " +
             number_text(max_pings) + " pings; at most limits.max_pings = " +
             std::to_string(limits.max_pings) + " of the scene file (docs/scene-format.md)");
  }
  // The seabed under the line, from its depth at the centre: the plane's rise over half the
  // line, 4 rms of the fBm and 3 ripple amplitudes; the sensor's excursions from its altitude:
  // the heave's peak, the altitude wander's (five sinusoids of sqrt(2/5) rms: sqrt(10) rms) and
  // a lagging altitude controller's, at most the relief's span, and at most its lag on the
  // steepest slope (slope x speed x time constant) plus the span of the bumps.
  const double slope = std::tan(s.slope_deg.hi * kRadPerDeg);
  const double bumps_m = 4.0 * s.roughness_rms_m.hi +
                         (s.ripples_probability > 0.0 ? 3.0 * s.ripple_amplitude_m.hi : 0.0);
  const double relief_m = slope * line_m / 2.0 + bumps_m;
  const double tau_s = knob_hi(s, "survey.altitude_time_constant_s");
  const double lag_m =
      tau_s > 0.0 ? std::min(2.0 * relief_m, slope * s.speed_m_s.hi * tau_s + 2.0 * bumps_m) : 0.0;
  const double motion_m = knob_hi(s, "survey.disturbance.heave_m") +
                          std::sqrt(10.0) * knob_hi(s, "survey.disturbance.altitude_m") + lag_m;
  const double lowest_m = rounded(s.altitude_m.lo, 3), highest_m = rounded(s.altitude_m.hi, 3);
  if (!(lowest_m > motion_m)) {
    fail("survey.altitude_m", range_text(s.altitude_m),
         "the lowest altitude > the sensor's motion about it (" + number_text(motion_m) +
             " m: survey.disturbance.heave_m, altitude_m, altitude_time_constant_s): the sensor "
             "must stay above the seabed");
  }
  if (!(rounded(s.depth_m.lo, 3) - relief_m > highest_m + motion_m)) {
    fail("seabed.depth_m", number_text(s.depth_m.lo),
         "the shallowest depth less the seabed's relief under the line (" + number_text(relief_m) +
             " m) > the highest survey.altitude_m (" + number_text(s.altitude_m.hi) +
             " m) plus the sensor's motion (" + number_text(motion_m) +
             " m): the towfish must stay in the water");
  }
  if (!(min_range_m > highest_m + motion_m)) {
    fail(s.range_m ? "sonar.range_m" : "sonar.preset",
         s.range_m ? range_text(*s.range_m) : join(s.sonar_preset.names),
         "the shortest range (" + number_text(min_range_m) + " m) > the highest altitude (" +
             number_text(highest_m) + " m) plus the sensor's motion (" + number_text(motion_m) +
             " m): every ping sees the seabed");
  }
  // The generator's own checks: the depth, the ripples on the grid.
  for (const double depth_m : {s.depth_m.lo, s.depth_m.hi}) {
    g.depth_m = rounded(depth_m, 3);
    try {
      g.validate();
    } catch (const InputError& e) {
      fail("seabed.depth_m", range_text(s.depth_m), e.what());
    }
  }
  if (s.ripples_probability > 0.0) {
    bathy::Ripples r;
    r.wavelength_m = rounded(s.ripple_wavelength_m.lo, 3);
    g.components = {r};
    try {
      g.validate_components();
    } catch (const InputError& e) {
      fail("seabed.ripples.wavelength_m", range_text(s.ripple_wavelength_m), e.what());
    }
  }
}

}  // namespace sonarsynth::dataset_spec
