// SPDX-License-Identifier: MIT
#pragma once
// Internal parts of the dataset specs (docs/dataset.md), shared by the files that read them and
// draw their items: dataset_spec.cpp (reading the spec), dataset_spec_bounds.cpp (the scene file's
// bounds on it), dataset_spec_objects.cpp (its object types) and dataset_item.cpp (item k's scene).

#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "sonarsynth/formats/config/dataset.hpp"
#include "sonarsynth/formats/config/yaml_fields.hpp"
#include "sonarsynth/object_types.hpp"

namespace sonarsynth::dataset_spec {

using yaml::Fields;

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;

/// `v` as text (shortest stream form), for messages.
std::string number_text(double v);
/// Fixed-point text: the scene file holds exactly the values the run uses.
std::string fx(double v, int decimals = 3);
/// `v` as the scene file holds it (fx) and as its reader reads it back.
double rounded(double v, int decimals);
/// "v" or "[lo, hi]", for messages.
std::string range_text(NumberRange r);
/// The names separated by ", ", for messages.
std::string join(const std::vector<std::string>& names);
/// A number or [lo, hi], each within [min, max] (min exclusive when `min_exclusive`).
NumberRange read_range(const Fields& f, const std::string& key, NumberRange fallback, double min,
                       double max, bool min_exclusive = false);

/// A name, a list of names or {name: weight}; every name must pass `valid` (else `valid_text`).
WeightedChoice read_choice(const Fields& f, const std::string& key, WeightedChoice fallback,
                           const std::function<bool(const std::string&)>& valid,
                           const std::string& valid_text);

/// Every value of `r` as the item's scene file will hold it (rounded to `decimals`) must be one
/// that the scene file accepts for `scene_key` (dataset_spec_bounds.cpp).
void check_scene_bound(const Fields& f, const std::string& key, NumberRange r, int decimals,
                       std::string_view scene_key);
/// A range of a key the scene file bounds: a number or [lo, hi] within `scene_key`'s bounds.
NumberRange read_scene_range(const Fields& f, const std::string& key, NumberRange fallback,
                             std::string_view scene_key, int decimals);

// Fields of the draws (ItemDraws keys); new fields take new numbers, existing ones keep theirs
// (a spec that does not use a new field draws the scene it drew before).
enum Field : std::uint64_t {
  kDepth = 1,
  kMaterial,
  kSlope,
  kSlopeAzimuth,
  kRoughRms,
  kRoughWavelength,
  kRipplesOn,
  kRippleWavelength,
  kRippleAmplitude,
  kRippleAzimuth,
  kObjectCount,
  kObject,  // sub = 16 * object + attribute (ObjectAttribute)
  kLineHeading,
  kAltitude,
  kSpeed,
  kPreset,
  kRange,
  kNoiseModel,
  kSnr,
  // Domain randomisation knobs (kKnobs).
  kFrequency = 20,
  kAltitudeTimeConstant,
  kRoll,
  kPitch,
  kYaw,
  kHeave,
  kDisturbancePeriod,
  kAltitudeWander,
  kHeadingWander,
  kWanderPeriod,
  kGain,
  kSeabedMedian,
  kTextureShape,
  kReflectivity,
  kRoughPersistence,
  kRippleBandwidth,
  kRippleVariation,
  kRippleAsymmetry,
};
static_assert(kSnr == 19 && kFrequency == 20, "existing fields keep their numbers");

// Attributes of object k (sub-index 16 k + attribute of kObject).
enum ObjectAttribute : std::uint64_t {
  kType = 0,
  kAlong = 1,
  kAcross = 2,
  kSide = 3,
  kHeading = 4,
  kEmbed = 5,
  kDiameter = 6,
  kLength = 7,
  kWidth = 8,
  kHeight = 9,
  kModel = 10,
  kScale = 11,
};

// An optional knob of domain randomisation: a spec key whose last part is the key it sets in the
// scene file, the scene key that bounds it, its draw field and its decimals in the scene file.
struct Knob {
  std::string_view key;
  std::string_view scene_key;
  Field field;
  int decimals;
};

// docs/dataset.md, "Domain randomisation": one line per knob.
inline constexpr Knob kKnobs[] = {
    {"seabed.texture_shape", "materials.texture_shape", kTextureShape, 3},
    {"seabed.reflectivity", "materials.reflectivity", kReflectivity, 4},
    {"seabed.roughness.persistence", "bathymetry.generate.components.fbm.persistence",
     kRoughPersistence, 3},
    {"seabed.ripples.bandwidth", "bathymetry.generate.components.ripples.bandwidth",
     kRippleBandwidth, 3},
    {"seabed.ripples.amplitude_variation",
     "bathymetry.generate.components.ripples.amplitude_variation", kRippleVariation, 3},
    {"seabed.ripples.asymmetry", "bathymetry.generate.components.ripples.asymmetry",
     kRippleAsymmetry, 3},
    {"survey.altitude_time_constant_s", "survey.altitude_time_constant_s", kAltitudeTimeConstant,
     3},
    {"survey.disturbance.roll_deg", "survey.disturbance.roll_deg", kRoll, 3},
    {"survey.disturbance.pitch_deg", "survey.disturbance.pitch_deg", kPitch, 3},
    {"survey.disturbance.yaw_deg", "survey.disturbance.yaw_deg", kYaw, 3},
    {"survey.disturbance.heave_m", "survey.disturbance.heave_m", kHeave, 3},
    {"survey.disturbance.period_s", "survey.disturbance.period_s", kDisturbancePeriod, 3},
    {"survey.disturbance.altitude_m", "survey.disturbance.altitude_m", kAltitudeWander, 3},
    {"survey.disturbance.heading_wander_deg", "survey.disturbance.heading_wander_deg",
     kHeadingWander, 3},
    {"survey.disturbance.wander_period_s", "survey.disturbance.wander_period_s", kWanderPeriod, 3},
    {"sonar.frequency_khz", "sonar.frequency_khz", kFrequency, 3},
    {"output.gain_db", "output.gain_db", kGain, 2},
    {"output.seabed_median_dbfs", "output.seabed_median_dbfs", kSeabedMedian, 2},
};

inline std::string_view section_of(std::string_view key) {
  return key.substr(0, key.rfind('.'));
}
inline std::string name_of(std::string_view key) {
  return std::string(key.substr(key.rfind('.') + 1));
}

/// The highest value of knob `key`, or `fallback` (the scene's default) when it is left out.
double knob_hi(const DatasetSpec& s, const std::string& key, double fallback = 0.0);

// The object types of a spec (dataset_spec_objects.cpp).

// The object types a spec draws, in the order of the type pick's weights (DatasetSpec::
// object_types): a new type goes at the end, so that the specs without it draw as before.
inline constexpr std::string_view kSpecTypeOrder[] = {"rock", "box", "pipe", "moored", "mesh"};

/// The keys of `objects.types`: the types of the object table a spec draws.
std::set<std::string> spec_type_names();
/// The member of DatasetObjectType that holds the range of spec key `key` (ObjectSpecKey).
NumberRange DatasetObjectType::*range_member(std::string_view key);
/// An entry of `objects.types` (docs/dataset.md): its weight and the ranges of its keys.
DatasetObjectType read_object_type(const Fields& d, const ObjectType& type);

// An item's geometry and the constraints on it (dataset_spec_bounds.cpp).

/// Largest horizontal distance of a point of an object from its position, metres.
double max_object_extent_m(const DatasetSpec& s);
/// The side of an item's square grid: it holds the line and its swath whatever the heading, with
/// a margin for the largest object.
double grid_side_m(const DatasetSpec& s, double max_range_m);
/// The constraints of the scene file that tie several keys together, checked on the extremes of
/// the spec's ranges so that no drawn item fails them (docs/dataset.md, "Validation").
void check_item_constraints(const DatasetSpec& s);

}  // namespace sonarsynth::dataset_spec
