// SPDX-License-Identifier: MIT
#include "sonarsynth/scene_object.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sonarsynth/error.hpp"
#include "sonarsynth/object_types.hpp"

namespace sonarsynth {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Clips the line p + s d to the slab lo <= coordinate <= hi; updates [s0, s1].
bool clip_slab(double p, double d, double lo, double hi, double& s0, double& s1) {
  if (d == 0.0) return p >= lo && p <= hi;
  double a = (lo - p) / d, b = (hi - p) / d;
  if (a > b) std::swap(a, b);
  s0 = std::max(s0, a);
  s1 = std::min(s1, b);
  return s0 <= s1;
}

}  // namespace

const char* to_string(ObjectShape s) {
  return shape_info(s).name.data();
}

Eigen::Vector2d ObjectPrimitive::axis_u() const {
  return {std::sin(heading_rad), std::cos(heading_rad)};
}

Eigen::Vector2d ObjectPrimitive::body_from_local(const Eigen::Vector2d& xy_m) const {
  const Eigen::Vector2d d = xy_m - centre_xy_m;
  const double sh = std::sin(heading_rad), ch = std::cos(heading_rad);
  // u along (sin h, cos h); v to its right, along (cos h, -sin h).
  return {d.x() * sh + d.y() * ch, d.x() * ch - d.y() * sh};
}

double ObjectPrimitive::base_at(double u_m) const {
  if (base_z_m.empty()) return 0.0;
  if (base_z_m.size() == 1 || base_step_m <= 0.0) return base_z_m.front();
  const double f = std::clamp((u_m + half_extent_m.x()) / base_step_m, 0.0,
                              static_cast<double>(base_z_m.size() - 1));
  const std::size_t i = std::min(static_cast<std::size_t>(f), base_z_m.size() - 2);
  const double w = f - static_cast<double>(i);
  return (1.0 - w) * base_z_m[i] + w * base_z_m[i + 1];
}

bool ObjectPrimitive::vertical_extent(double x_m, double y_m, double& z_bottom_m,
                                      double& z_top_m) const {
  const Eigen::Vector2d uv = body_from_local({x_m, y_m});
  const double hu = half_extent_m.x(), hv = half_extent_m.y(), hz = half_extent_m.z();
  switch (shape) {
    case ObjectShape::kMesh:
      return mesh && mesh->vertical_extent(x_m, y_m, z_bottom_m, z_top_m);
    case ObjectShape::kBox: {
      if (std::abs(uv.x()) > hu || std::abs(uv.y()) > hv) return false;
      z_bottom_m = base_at(uv.x());
      z_top_m = z_bottom_m + 2.0 * hz;
      return true;
    }
    case ObjectShape::kCylinder: {
      if (std::abs(uv.x()) > hu || std::abs(uv.y()) > hv) return false;
      const double axis_z = base_at(uv.x()) + hz;
      const double half = hz * std::sqrt(std::max(0.0, 1.0 - (uv.y() / hv) * (uv.y() / hv)));
      z_bottom_m = axis_z - half;
      z_top_m = axis_z + half;
      return true;
    }
    case ObjectShape::kEllipsoid: {
      const double q = (uv.x() / hu) * (uv.x() / hu) + (uv.y() / hv) * (uv.y() / hv);
      if (q > 1.0) return false;
      const double centre_z = base_at(0.0) + hz;
      const double half = hz * std::sqrt(1.0 - q);
      z_bottom_m = centre_z - half;
      z_top_m = centre_z + half;
      return true;
    }
  }
  return false;
}

bool ObjectPrimitive::footprint_interval(const Eigen::Vector2d& start_m, const Eigen::Vector2d& dir,
                                         double& s0_m, double& s1_m) const {
  const Eigen::Vector2d b0 = body_from_local(start_m);
  const double sh = std::sin(heading_rad), ch = std::cos(heading_rad);
  const Eigen::Vector2d bd(dir.x() * sh + dir.y() * ch, dir.x() * ch - dir.y() * sh);
  const double hu = half_extent_m.x(), hv = half_extent_m.y();
  if (shape == ObjectShape::kEllipsoid) {
    // (u/hu)^2 + (v/hv)^2 = 1 along the line: a s^2 + b s + c = 0.
    const double a = (bd.x() / hu) * (bd.x() / hu) + (bd.y() / hv) * (bd.y() / hv);
    const double b = 2.0 * (b0.x() * bd.x() / (hu * hu) + b0.y() * bd.y() / (hv * hv));
    const double c = (b0.x() / hu) * (b0.x() / hu) + (b0.y() / hv) * (b0.y() / hv) - 1.0;
    const double disc = b * b - 4.0 * a * c;
    if (a <= 0.0 || disc < 0.0) return false;
    const double sq = std::sqrt(disc);
    s0_m = (-b - sq) / (2.0 * a);
    s1_m = (-b + sq) / (2.0 * a);
    return true;
  }
  s0_m = -kInf;
  s1_m = kInf;
  return clip_slab(b0.x(), bd.x(), -hu, hu, s0_m, s1_m) &&
         clip_slab(b0.y(), bd.y(), -hv, hv, s0_m, s1_m);
}

Eigen::Vector4d ObjectPrimitive::bbox() const {
  const Eigen::Vector2d u = axis_u();
  const Eigen::Vector2d v(u.y(), -u.x());
  const double hu = half_extent_m.x(), hv = half_extent_m.y();
  const double ex = std::abs(u.x()) * hu + std::abs(v.x()) * hv;
  const double ey = std::abs(u.y()) * hu + std::abs(v.y()) * hv;
  return {centre_xy_m.x() - ex, centre_xy_m.y() - ey, centre_xy_m.x() + ex, centre_xy_m.y() + ey};
}

void ObjectPrimitive::validate(const std::string& what) const {
  auto positive = [&](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) {
      throw InputError(what + ": " + name + " = " + std::to_string(v) +
                       ". Violated constraint: " + name + " > 0");
    }
  };
  positive(half_extent_m.x(), shape_info(shape).size_u.data());
  positive(half_extent_m.y(), shape_info(shape).size_v.data());
  positive(half_extent_m.z(), "height");
  if (id <= 0) {
    throw InputError(what + ": id = " + std::to_string(id) + ". Violated constraint: id > 0");
  }
  if (!centre_xy_m.allFinite() || !std::isfinite(heading_rad)) {
    throw InputError(what + ": position or heading is not finite");
  }
}

void ObjectPrimitive::place_on_seabed(const HeightGrid& seabed, double gap_m, double embed_fraction,
                                      const std::string& what) {
  validate(what);
  if (!(gap_m >= 0.0)) {
    throw InputError(what + ": clearance_m = " + std::to_string(gap_m) +
                     ". Violated constraint: clearance_m >= 0");
  }
  if (!(embed_fraction >= 0.0 && embed_fraction < 1.0)) {
    throw InputError(what + ": embed = " + std::to_string(embed_fraction) +
                     ". Violated constraint: 0 <= embed < 1");
  }
  const double lift = gap_m - embed_fraction * 2.0 * half_extent_m.z();
  clearance_m = gap_m;
  auto seabed_at = [&](const Eigen::Vector2d& p) {
    const double z = seabed.height_m(p.x(), p.y());
    if (std::isnan(z)) {
      throw InputError(what +
                       ": lies outside the bathymetry grid or over a nodata hole at local (" +
                       std::to_string(p.x()) + ", " + std::to_string(p.y()) + ") m");
    }
    return z;
  };
  base_z_m.clear();
  if (shape == ObjectShape::kCylinder) {
    // Drape along the axis at the grid spacing (a long pipe follows the seabed).
    const GridGeometry& g = seabed.geometry();
    const double step = std::min(g.dx_m, std::abs(g.dy_m));
    const double len = 2.0 * half_extent_m.x();
    const std::size_t n = static_cast<std::size_t>(std::ceil(len / step)) + 1;
    base_step_m = len / static_cast<double>(n - 1);
    const Eigen::Vector2d u = axis_u();
    for (std::size_t i = 0; i < n; ++i) {
      const double s = -half_extent_m.x() + base_step_m * static_cast<double>(i);
      base_z_m.push_back(static_cast<float>(seabed_at(centre_xy_m + s * u) + lift));
    }
  } else {
    // Check the four footprint corners too, so an object over the grid edge is an error.
    const Eigen::Vector2d u = axis_u(), v(u.y(), -u.x());
    for (double a : {-1.0, 1.0}) {
      for (double b : {-1.0, 1.0}) {
        seabed_at(centre_xy_m + a * half_extent_m.x() * u + b * half_extent_m.y() * v);
      }
    }
    base_step_m = 0.0;
    base_z_m.push_back(static_cast<float>(seabed_at(centre_xy_m) + lift));
  }
}

ObjectPrimitive place_mesh(TriangleMesh model, const MeshPlacement& where, const HeightGrid& seabed,
                           std::int32_t id, std::uint16_t material, const std::string& what) {
  if (model.triangle.empty()) throw InputError(what + ": the mesh has no triangles");
  if (!(where.scale.minCoeff() > 0.0) || !where.scale.allFinite()) {
    throw InputError(what + ": scale = (" + std::to_string(where.scale.x()) + ", " +
                     std::to_string(where.scale.y()) + ", " + std::to_string(where.scale.z()) +
                     "). Violated constraint: every scale > 0");
  }
  if (!where.position_xy_m.allFinite() || !std::isfinite(where.heading_rad)) {
    throw InputError(what + ": position or heading is not finite");
  }
  if (!(where.clearance_m >= 0.0)) {
    throw InputError(what + ": clearance_m = " + std::to_string(where.clearance_m) +
                     ". Violated constraint: clearance_m >= 0");
  }
  if (!(where.embed_fraction >= 0.0 && where.embed_fraction < 1.0)) {
    throw InputError(what + ": embed = " + std::to_string(where.embed_fraction) +
                     ". Violated constraint: 0 <= embed < 1");
  }
  for (auto& v : model.vertex_m) v = v.cwiseProduct(where.scale);
  Eigen::Vector3d lo, hi;
  model.build_index(what);  // checks indices and finiteness first
  model.bounds(lo, hi);
  const double sh = std::sin(where.heading_rad), ch = std::cos(where.heading_rad);
  const Eigen::Vector2d fwd(sh, ch), port(-ch, sh);
  const Eigen::Vector2d c = where.position_xy_m;
  // The footprint box (model bounds turned to the heading); every corner over the seabed.
  ObjectPrimitive p;
  p.shape = ObjectShape::kMesh;
  p.id = id;
  p.material = material;
  p.heading_rad = where.heading_rad;
  p.centre_xy_m = c + 0.5 * (lo.x() + hi.x()) * fwd + 0.5 * (lo.y() + hi.y()) * port;
  p.half_extent_m = (0.5 * (hi - lo)).cwiseMax(Eigen::Vector3d::Constant(1e-3));
  auto seabed_at = [&](const Eigen::Vector2d& q) {
    const double z = seabed.height_m(q.x(), q.y());
    if (std::isnan(z)) {
      throw InputError(what +
                       ": lies outside the bathymetry grid or over a nodata hole at local (" +
                       std::to_string(q.x()) + ", " + std::to_string(q.y()) + ") m");
    }
    return z;
  };
  for (double a : {lo.x(), hi.x()}) {
    for (double b : {lo.y(), hi.y()}) seabed_at(c + a * fwd + b * port);
  }
  // Rounded as the primitives' bases are (base_z_m is float), so a mesh box is the box.
  const double base = static_cast<float>(seabed_at(c) + where.clearance_m -
                                         where.embed_fraction * (hi.z() - lo.z()));
  for (auto& v : model.vertex_m) {
    const Eigen::Vector2d q = c + v.x() * fwd + v.y() * port;
    v = {q.x(), q.y(), v.z() - lo.z() + base};
  }
  model.build_index(what);
  p.base_z_m = {static_cast<float>(base)};
  p.base_step_m = 0.0;
  p.clearance_m = where.clearance_m;
  p.validate(what);
  p.mesh = std::make_shared<const TriangleMesh>(std::move(model));
  return p;
}

void ObjectSet::add(ObjectPrimitive p) {
  primitives_.push_back(std::move(p));
  bucket_start_.clear();  // index is stale
}

void ObjectSet::build_index(double bucket_size_m) {
  bucket_start_.clear();
  bucket_items_.clear();
  if (primitives_.empty()) return;
  bucket_m_ = bucket_size_m;
  Eigen::Vector4d all(kInf, kInf, -kInf, -kInf);
  for (const auto& p : primitives_) {
    const Eigen::Vector4d b = p.bbox();
    all = {std::min(all[0], b[0]), std::min(all[1], b[1]), std::max(all[2], b[2]),
           std::max(all[3], b[3])};
  }
  origin_m_ = {all[0], all[1]};
  bucket_cols_ = static_cast<std::size_t>(std::floor((all[2] - all[0]) / bucket_m_)) + 1;
  bucket_rows_ = static_cast<std::size_t>(std::floor((all[3] - all[1]) / bucket_m_)) + 1;
  const std::size_t nb = bucket_cols_ * bucket_rows_;
  // Two passes (count, fill): a compressed list per bucket.
  std::vector<std::uint32_t> count(nb + 1, 0);
  auto for_buckets = [&](const ObjectPrimitive& p, auto&& f) {
    const Eigen::Vector4d b = p.bbox();
    const auto c0 = static_cast<std::size_t>((b[0] - origin_m_.x()) / bucket_m_);
    const auto r0 = static_cast<std::size_t>((b[1] - origin_m_.y()) / bucket_m_);
    const auto c1 =
        std::min(bucket_cols_ - 1, static_cast<std::size_t>((b[2] - origin_m_.x()) / bucket_m_));
    const auto r1 =
        std::min(bucket_rows_ - 1, static_cast<std::size_t>((b[3] - origin_m_.y()) / bucket_m_));
    for (std::size_t r = r0; r <= r1; ++r) {
      for (std::size_t c = c0; c <= c1; ++c) f(r * bucket_cols_ + c);
    }
  };
  for (const auto& p : primitives_) for_buckets(p, [&](std::size_t b) { ++count[b + 1]; });
  for (std::size_t b = 0; b < nb; ++b) count[b + 1] += count[b];
  bucket_start_ = count;
  bucket_items_.resize(count[nb]);
  std::vector<std::uint32_t> fill(count.begin(), count.end() - 1);
  for (std::uint32_t i = 0; i < primitives_.size(); ++i) {
    for_buckets(primitives_[i], [&](std::size_t b) { bucket_items_[fill[b]++] = i; });
  }
}

void ObjectSet::candidates_along(const Eigen::Vector2d& start_m, const Eigen::Vector2d& dir,
                                 double length_m, std::vector<std::uint32_t>& out) const {
  out.clear();
  if (primitives_.empty()) return;
  if (bucket_start_.empty()) throw Error("object set: build_index() was not called");
  // Amanatides-Woo traversal of the buckets the segment crosses, after clipping to the index.
  const Eigen::Vector2d p = (start_m - origin_m_) / bucket_m_;
  double s0 = 0.0, s1 = length_m / bucket_m_;
  if (!clip_slab(p.x(), dir.x(), 0.0, static_cast<double>(bucket_cols_), s0, s1) ||
      !clip_slab(p.y(), dir.y(), 0.0, static_cast<double>(bucket_rows_), s0, s1)) {
    return;
  }
  const Eigen::Vector2d q = p + s0 * dir;
  auto c = static_cast<long>(std::min(std::floor(q.x()), static_cast<double>(bucket_cols_ - 1)));
  auto r = static_cast<long>(std::min(std::floor(q.y()), static_cast<double>(bucket_rows_ - 1)));
  const long step_c = dir.x() > 0 ? 1 : -1, step_r = dir.y() > 0 ? 1 : -1;
  double next_c = dir.x() != 0 ? ((static_cast<double>(c) + (step_c > 0)) - p.x()) / dir.x() : kInf;
  double next_r = dir.y() != 0 ? ((static_cast<double>(r) + (step_r > 0)) - p.y()) / dir.y() : kInf;
  const double dc = dir.x() != 0 ? std::abs(1.0 / dir.x()) : kInf;
  const double dr = dir.y() != 0 ? std::abs(1.0 / dir.y()) : kInf;
  while (c >= 0 && r >= 0 && c < static_cast<long>(bucket_cols_) &&
         r < static_cast<long>(bucket_rows_)) {
    const std::size_t b = static_cast<std::size_t>(r) * bucket_cols_ + static_cast<std::size_t>(c);
    out.insert(out.end(), bucket_items_.begin() + bucket_start_[b],
               bucket_items_.begin() + bucket_start_[b + 1]);
    if (std::min(next_c, next_r) > s1) break;
    if (next_c < next_r) {
      c += step_c;
      next_c += dc;
    } else {
      r += step_r;
      next_r += dr;
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

double ObjectSet::top_at(double x_m, double y_m, std::int32_t* id) const {
  double best = std::numeric_limits<double>::quiet_NaN();
  std::int32_t best_id = 0;
  for (const auto& p : primitives_) {
    double zb = 0, zt = 0;
    if (p.vertical_extent(x_m, y_m, zb, zt) && !(zt <= best)) {
      best = zt;
      best_id = p.id;
    }
  }
  if (id) *id = best_id;
  return best;
}

}  // namespace sonarsynth
