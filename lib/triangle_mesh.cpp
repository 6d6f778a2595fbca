// SPDX-License-Identifier: MIT
#include "sonarsynth/triangle_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace {

constexpr std::uint32_t kLeafSize = 4;
constexpr double kInf = std::numeric_limits<double>::infinity();

struct Box2 {
  double lo_x = kInf, lo_y = kInf, hi_x = -kInf, hi_y = -kInf;
  void add(const Eigen::Vector3d& p) {
    lo_x = std::min(lo_x, p.x());
    lo_y = std::min(lo_y, p.y());
    hi_x = std::max(hi_x, p.x());
    hi_y = std::max(hi_y, p.y());
  }
};

}  // namespace

void TriangleMesh::build_index(const std::string& what) {
  const std::size_t nv = vertex_m.size(), nt = triangle.size();
  if (material.size() != nt) {
    throw InputError(what + ": " + std::to_string(material.size()) + " materials for " +
                     std::to_string(nt) + " triangles. Violated constraint: one per triangle");
  }
  if (nt >= std::numeric_limits<std::uint32_t>::max() / 2) {
    throw InputError(what + ": " + std::to_string(nt) + " triangles. Violated constraint: < 2^31");
  }
  for (std::size_t v = 0; v < nv; ++v) {
    if (!vertex_m[v].allFinite()) {
      throw InputError(what + ": vertex " + std::to_string(v) + " is not finite");
    }
  }
  for (std::size_t t = 0; t < nt; ++t) {
    for (const std::uint32_t i : triangle[t]) {
      if (i >= nv) {
        throw InputError(what + ": triangle " + std::to_string(t) + " names vertex " +
                         std::to_string(i) + ". Violated constraint: index < " +
                         std::to_string(nv) + " vertices");
      }
    }
  }
  nodes.clear();
  order.resize(nt);
  for (std::uint32_t t = 0; t < nt; ++t) order[t] = t;
  if (nt == 0) return;
  std::vector<Eigen::Vector2d> centre(nt);
  std::vector<Box2> box(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    for (const std::uint32_t i : triangle[t]) box[t].add(vertex_m[i]);
    centre[t] = {0.5 * (box[t].lo_x + box[t].hi_x), 0.5 * (box[t].lo_y + box[t].hi_y)};
  }
  // Top-down median split on the longer side of the centres' bounds (iterative, explicit stack).
  struct Task {
    std::uint32_t node, first, count;
  };
  std::vector<Task> stack;
  nodes.push_back({});
  stack.push_back({0, 0, static_cast<std::uint32_t>(nt)});
  while (!stack.empty()) {
    const Task k = stack.back();
    stack.pop_back();
    Box2 b, c;
    for (std::uint32_t i = k.first; i < k.first + k.count; ++i) {
      const Box2& tb = box[order[i]];
      b.lo_x = std::min(b.lo_x, tb.lo_x);
      b.lo_y = std::min(b.lo_y, tb.lo_y);
      b.hi_x = std::max(b.hi_x, tb.hi_x);
      b.hi_y = std::max(b.hi_y, tb.hi_y);
      c.add({centre[order[i]].x(), centre[order[i]].y(), 0.0});
    }
    nodes[k.node] = {b.lo_x, b.lo_y, b.hi_x, b.hi_y, k.first, k.count};
    if (k.count <= kLeafSize) continue;
    const int axis = (c.hi_x - c.lo_x) >= (c.hi_y - c.lo_y) ? 0 : 1;
    const std::uint32_t half = k.count / 2;
    const auto first = order.begin() + k.first;
    std::nth_element(first, first + half, first + k.count, [&](std::uint32_t a, std::uint32_t b2) {
      return centre[a][axis] < centre[b2][axis];
    });
    // Inner node: its children are consecutive, `first` names the left one.
    const auto left = static_cast<std::uint32_t>(nodes.size());
    const std::uint32_t right = left + 1;
    nodes.push_back({});
    nodes.push_back({});
    nodes[k.node].first = left;
    nodes[k.node].count = 0;
    stack.push_back({right, k.first + half, k.count - half});
    stack.push_back({left, k.first, half});
  }
}

void TriangleMesh::triangles_near_plane(const Eigen::Vector2d& origin_xy_m,
                                        const Eigen::Vector2d& dir,
                                        std::vector<std::uint32_t>& out) const {
  out.clear();
  if (nodes.empty()) return;
  // Plane normal (horizontal): signed distance d = (p - origin) . n.
  const Eigen::Vector2d n(dir.y(), -dir.x());
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const std::uint32_t idx = stack[--top];
    const Node& nd = nodes[idx];
    const double x0 = nd.lo_x - origin_xy_m.x(), x1 = nd.hi_x - origin_xy_m.x();
    const double y0 = nd.lo_y - origin_xy_m.y(), y1 = nd.hi_y - origin_xy_m.y();
    // Interval of a linear function over the box: sum of per-axis extremes.
    const auto range = [&](const Eigen::Vector2d& a, double& lo, double& hi) {
      lo = std::min(a.x() * x0, a.x() * x1) + std::min(a.y() * y0, a.y() * y1);
      hi = std::max(a.x() * x0, a.x() * x1) + std::max(a.y() * y0, a.y() * y1);
    };
    double dlo = 0, dhi = 0;
    range(n, dlo, dhi);
    const double tol = 1e-9 * (1.0 + std::abs(x0) + std::abs(x1) + std::abs(y0) + std::abs(y1));
    if (dlo > tol || dhi < -tol) continue;
    if (nd.count > 0) {
      out.insert(out.end(), order.begin() + nd.first, order.begin() + nd.first + nd.count);
    } else if (top + 2 <= 64) {
      stack[top++] = nd.first + 1;  // right child
      stack[top++] = nd.first;      // left child
    }
  }
}

bool TriangleMesh::vertical_extent(double x_m, double y_m, double& z_bottom_m,
                                   double& z_top_m) const {
  bool any = false;
  z_bottom_m = kInf;
  z_top_m = -kInf;
  for (const auto& t : triangle) {
    const Eigen::Vector3d &a = vertex_m[t[0]], &b = vertex_m[t[1]], &c = vertex_m[t[2]];
    const double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (det == 0.0) continue;  // vertical or degenerate: the neighbours give its heights
    const double l1 = ((x_m - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (y_m - a.y())) / det;
    const double l2 = ((b.x() - a.x()) * (y_m - a.y()) - (x_m - a.x()) * (b.y() - a.y())) / det;
    if (l1 < 0.0 || l2 < 0.0 || l1 + l2 > 1.0) continue;
    const double z = a.z() + l1 * (b.z() - a.z()) + l2 * (c.z() - a.z());
    z_bottom_m = std::min(z_bottom_m, z);
    z_top_m = std::max(z_top_m, z);
    any = true;
  }
  return any;
}

void TriangleMesh::bounds(Eigen::Vector3d& lo_m, Eigen::Vector3d& hi_m) const {
  lo_m = Eigen::Vector3d::Constant(kInf);
  hi_m = Eigen::Vector3d::Constant(-kInf);
  for (const auto& v : vertex_m) {
    lo_m = lo_m.cwiseMin(v);
    hi_m = hi_m.cwiseMax(v);
  }
}

}  // namespace sonarsynth
