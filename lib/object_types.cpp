// SPDX-License-Identifier: MIT
// The object vocabulary (docs/scene-format.md "objects", docs/dataset.md objects.types).
#include "sonarsynth/object_types.hpp"

#include <array>
#include <sstream>

namespace sonarsynth {
namespace {

using std::string_view_literals::operator""sv;

constexpr double kMaxSizeM = 1000.0;  // a box or wreck part side: a ship, not a typo
constexpr double kMaxDiameterM = 1e3;
constexpr double kMaxLengthM = 1e5;

constexpr std::string_view kSizeForm = "each of [length, width, height]";

constexpr ObjectParam kDiameter{"diameter_m", "m", 0.0, kMaxDiameterM, true};
constexpr ObjectParam kLength{"length_m", "m", 0.0, kMaxLengthM, true};
constexpr ObjectParam kSize{"size_m", "m", 0.0, kMaxSizeM, true, kSizeForm};

constexpr ObjectParam kCommon[] = {
    {"clearance_m", "m", 0.0, 1e4},  // gap between the seabed and the body
    {"embed", "", 0.0, 0.99},        // fraction of the height below the seabed
    {"lift_m", "m", 0.0, 1e3},       // a wreck part's height above the wreck's base
};

constexpr std::string_view kPipeKeys[] = {"type",     "id",          "name",        "material",
                                          "position", "heading_deg", "length_m",    "start",
                                          "end",      "diameter_m",  "clearance_m", "embed"};
constexpr std::string_view kBlockKeys[] = {"type",        "id",          "name",   "material",
                                           "position",    "heading_deg", "size_m", "diameter_m",
                                           "clearance_m", "embed"};
constexpr std::string_view kWreckKeys[] = {
    "type", "id", "name", "material", "position", "heading_deg", "parts", "clearance_m", "embed"};
constexpr std::string_view kWreckPartKeys[] = {"offset_m", "size_m", "heading_deg", "lift_m"};
constexpr std::string_view kMooredKeys[] = {"type",     "id",          "name",  "material",
                                            "position", "heading_deg", "shape", "diameter_m",
                                            "length_m", "height_m"};
constexpr std::string_view kMeshKeys[] = {
    "type", "id",    "name",           "material", "position",    "heading_deg",
    "file", "scale", "face_materials", "up_axis",  "clearance_m", "embed"};

constexpr ObjectParam kPipeParams[] = {kDiameter, kLength};
constexpr ObjectParam kBoxParams[] = {kSize};
constexpr ObjectParam kRockParams[] = {kSize, kDiameter};
constexpr ObjectParam kWreckParams[] = {kSize};
constexpr ObjectParam kMooredParams[] = {kDiameter, kLength, {"height_m", "m", 0.0, 1e4, true}};
constexpr ObjectParam kMeshParams[] = {
    {"scale", "", 0.0, 1e4, true, "one number or each of [x, y, z]"}};

// A dataset spec's keys, in the order an item's scene file writes them.
constexpr ObjectSpecKey kRockSpec[] = {{"diameter_m", "diameter_m", 0, 1.0}};
constexpr ObjectSpecKey kBoxSpec[] = {
    {"length_m", "size_m", 0, 2.0}, {"width_m", "size_m", 1, 1.0}, {"height_m", "size_m", 2, 1.0}};
constexpr ObjectSpecKey kPipeSpec[] = {{"length_m", "length_m", 0, 20.0},
                                       {"diameter_m", "diameter_m", 0, 0.3}};
constexpr ObjectSpecKey kMooredSpec[] = {{"diameter_m", "diameter_m", 0, 1.0},
                                         {"height_m", "height_m", 0, 3.0}};
constexpr ObjectSpecKey kMeshSpec[] = {{"scale", "scale", 0, 1.0}};

const ObjectType kTypes[] = {
    {"pipe",
     ObjectShape::kCylinder,
     "steel",
     kPipeKeys,
     {},
     kPipeParams,
     kPipeSpec,
     "{type: pipe, position: {east_m: 0, north_m: 0}, heading_deg: 30, length_m: 20, "
     "diameter_m: 0.3}"},
    {"cylinder",
     ObjectShape::kCylinder,
     "steel",
     kPipeKeys,
     {},
     kPipeParams,
     {},
     "{type: cylinder, start: {east_m: -5, north_m: 0}, end: {east_m: 5, north_m: 0}, "
     "diameter_m: 0.5, clearance_m: 0.5}"},
    {"box",
     ObjectShape::kBox,
     "steel",
     kBlockKeys,
     {},
     kBoxParams,
     kBoxSpec,
     "{type: box, position: {east_m: 0, north_m: 0}, heading_deg: 35, size_m: [2, 1, 1]}"},
    {"rock",
     ObjectShape::kEllipsoid,
     "rock",
     kBlockKeys,
     {},
     kRockParams,
     kRockSpec,
     "{type: rock, position: {east_m: 0, north_m: 0}, diameter_m: 1, embed: 0.2}"},
    {"wreck",
     ObjectShape::kBox,
     "steel",
     kWreckKeys,
     kWreckPartKeys,
     kWreckParams,
     {},
     "{type: wreck, position: {east_m: 0, north_m: 0}, heading_deg: 120, parts: [{offset_m: "
     "[0, 0], size_m: [18, 5, 2.5]}, {offset_m: [-4, 0], size_m: [5, 3.5, 2], lift_m: 2.5}]}"},
    {"moored",
     ObjectShape::kEllipsoid,
     "steel",
     kMooredKeys,
     {},
     kMooredParams,
     kMooredSpec,
     "{type: moored, position: {east_m: 0, north_m: 0}, shape: sphere, diameter_m: 1, "
     "height_m: 3}"},
    {"mesh",
     ObjectShape::kMesh,
     "steel",
     kMeshKeys,
     {},
     kMeshParams,
     kMeshSpec,
     "{type: mesh, file: models/mine.obj, position: {east_m: 0, north_m: 0}, scale: 1}"},
};

constexpr ObjectShapeInfo kShapes[] = {
    {ObjectShape::kCylinder, "cylinder", "length_m", "radius_m"},
    {ObjectShape::kBox, "box", "size x", "size y"},
    {ObjectShape::kEllipsoid, "ellipsoid", "size x", "size y"},
    {ObjectShape::kMesh, "mesh", "size x", "size y"},
};

}  // namespace

std::string ObjectParam::constraint(std::string_view as_key) const {
  const std::string_view name = as_key.empty() ? key : as_key;
  std::ostringstream c;
  c << name << (lo_open ? " > " : " >= ") << lo << " and <= " << hi;
  if (!form.empty() && as_key.empty()) c << " (" << form << ")";
  return c.str();
}

const ObjectParam* ObjectType::param(std::string_view k) const {
  for (const ObjectParam& p : params) {
    if (p.key == k) return &p;
  }
  for (const ObjectParam& p : kCommon) {
    if (p.key == k) return &p;
  }
  return nullptr;
}

bool ObjectType::takes(std::string_view k) const {
  for (const std::string_view key : keys) {
    if (key == k) return true;
  }
  return false;
}

std::span<const ObjectType> object_types() {
  return kTypes;
}

const ObjectType* find_object_type(std::string_view name) {
  for (const ObjectType& t : kTypes) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

std::string object_type_names(bool dataset_spec_only) {
  std::string names;
  for (const ObjectType& t : kTypes) {
    if (dataset_spec_only && !t.in_dataset_spec()) continue;
    names += (names.empty() ? ""sv : ", "sv);
    names += t.name;
  }
  return names;
}

std::span<const ObjectParam> object_common_params() {
  return kCommon;
}

const ObjectShapeInfo& shape_info(ObjectShape s) {
  for (const ObjectShapeInfo& i : kShapes) {
    if (i.shape == s) return i;
  }
  return kShapes[1];
}

}  // namespace sonarsynth
