// SPDX-License-Identifier: MIT
// The object vocabulary: one table of the object types that scene files (docs/scene-format.md
// "objects"), dataset specs (docs/dataset.md, objects.types) and Python (docs/python.md,
// add_object) name, with the parameters each takes, their units, bounds and defaults. Every
// front end reads names, keys and bound checks from here, so a bad value gives the same
// "Violated constraint" text from all three.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "sonarsynth/scene_object.hpp"

namespace sonarsynth {

/// One numeric parameter of an object entry, as files and Python spell it.
struct ObjectParam {
  std::string_view key;   ///< the key in a scene file's entry ("diameter_m")
  std::string_view unit;  ///< "m", "deg" or "" (a fraction, a factor)
  double lo = 0.0;        ///< lowest value (excluded when lo_open)
  double hi = 0.0;        ///< highest value (included)
  bool lo_open = false;
  /// How the value is written when it is not one number ("[length, width, height]").
  std::string_view form = "";

  bool accepts(double v) const { return (lo_open ? v > lo : v >= lo) && v <= hi; }
  /// The allowed range as messages state it: "diameter_m > 0 and <= 1000" (and the form, if
  /// any). A dataset spec names `as_key` (the parts of size_m: length_m, width_m, height_m; the
  /// range of a scale) and gets no form.
  std::string constraint(std::string_view as_key = {}) const;
};

/// A key of a dataset spec's `objects.types.<type>` map: a range drawn for `param` (or its
/// element `index`, for size_m), `spec_default` when the spec leaves it out.
struct ObjectSpecKey {
  std::string_view key;    ///< as the spec spells it ("length_m")
  std::string_view param;  ///< the ObjectParam it draws ("size_m")
  std::size_t index = 0;   ///< element of a list parameter
  double spec_default = 0.0;
};

/// One object type.
struct ObjectType {
  std::string_view name;  ///< as written in files and Python ("pipe")
  /// The primitive it becomes: a wreck's parts are boxes; a moored target is an ellipsoid
  /// (sphere) or a cylinder as its `shape` says.
  ObjectShape shape;
  std::string_view default_material;
  /// Every key its scene-file entry takes (the common ones included).
  std::span<const std::string_view> keys;
  /// The keys of each of its `parts` (a wreck's boxes); empty for the other types.
  std::span<const std::string_view> part_keys;
  /// Its numeric parameters (the common ones are object_common_params()).
  std::span<const ObjectParam> params;
  /// The keys of its dataset-spec entry besides `weight`, in the order the item's scene file
  /// writes them; empty if a spec cannot draw it.
  std::span<const ObjectSpecKey> spec_keys;
  /// A valid scene-file entry, flow YAML, positions {east_m, north_m} around the grid centre
  /// (docs/scene-format.md "objects"); files are relative to the repository's samples/.
  std::string_view example;

  /// The parameter `key` (its own or a common one); nullptr if it has none.
  const ObjectParam* param(std::string_view key) const;
  /// Whether its scene-file entry takes `key`.
  bool takes(std::string_view key) const;
  bool in_dataset_spec() const { return !spec_keys.empty(); }
};

/// Every object type, in the order the docs list them.
std::span<const ObjectType> object_types();
/// The type called `name`; nullptr if there is none.
const ObjectType* find_object_type(std::string_view name);
/// "pipe, cylinder, box, rock, wreck, moored, mesh" (for "one of ..." messages).
std::string object_type_names(bool dataset_spec_only = false);
/// Parameters every type with them shares: clearance_m, embed, lift_m (a wreck part's).
std::span<const ObjectParam> object_common_params();

/// What the renderer's primitives are called in the products and messages.
struct ObjectShapeInfo {
  ObjectShape shape;
  std::string_view name;  ///< "cylinder", "box", "ellipsoid", "mesh"
  /// Names of the half sizes (u, v) in validate()'s messages.
  std::string_view size_u, size_v;
};
const ObjectShapeInfo& shape_info(ObjectShape s);

}  // namespace sonarsynth
