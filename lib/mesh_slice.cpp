// SPDX-License-Identifier: MIT
// Mesh objects cut by the beam plane into closed sections (docs/physics.md §2.1).
#include "sonarsynth/mesh_slice.hpp"

#include <algorithm>
#include <cmath>

namespace sonarsynth {
namespace {

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

// Appends node (y, z) whose facet to the next node has material m, dropping zero-length facets
// and merging a node that continues its predecessor's facet in a straight line (same material).
void push_node(std::vector<double>& ys, std::vector<double>& zs, std::vector<std::uint16_t>& ms,
               double y, double z, std::uint16_t m) {
  const std::size_t n = ys.size();
  if (n > 0 && ys[n - 1] == y && zs[n - 1] == z) {
    ms[n - 1] = m;  // the zero-length facet goes; the node keeps the next facet's material
    return;
  }
  if (n > 1 && ms[n - 2] == ms[n - 1]) {
    const double uy = ys[n - 1] - ys[n - 2], uz = zs[n - 1] - zs[n - 2];
    const double vy = y - ys[n - 1], vz = z - zs[n - 1];
    const double cross = uy * vz - uz * vy, dot = uy * vy + uz * vz;
    if (dot > 0.0 && std::abs(cross) <= 1e-10 * std::hypot(uy, uz) * std::hypot(vy, vz)) {
      ys[n - 1] = y;
      zs[n - 1] = z;
      ms[n - 1] = m;
      return;
    }
  }
  ys.push_back(y);
  zs.push_back(z);
  ms.push_back(m);
}

// The same across the closing facet (last node to the first) of a closed polygon.
void close_polygon(std::vector<double>& ys, std::vector<double>& zs,
                   std::vector<std::uint16_t>& ms) {
  for (int pass = 0; pass < 4 && ys.size() >= 3; ++pass) {
    const std::size_t n = ys.size();
    if (ys[n - 1] == ys[0] && zs[n - 1] == zs[0]) {  // zero-length closing facet
      ys.pop_back();
      zs.pop_back();
      ms.pop_back();
      continue;
    }
    // Node 0 continues the closing facet in a straight line: drop it.
    if (ms[n - 1] == ms[0]) {
      const double uy = ys[0] - ys[n - 1], uz = zs[0] - zs[n - 1];
      const double vy = ys[1] - ys[0], vz = zs[1] - zs[0];
      const double cross = uy * vz - uz * vy, dot = uy * vy + uz * vz;
      if (dot > 0.0 && std::abs(cross) <= 1e-10 * std::hypot(uy, uz) * std::hypot(vy, vz)) {
        ys.erase(ys.begin());
        zs.erase(zs.begin());
        ms.erase(ms.begin());
        continue;
      }
    }
    break;
  }
}

// Emits the polygon (py, pz, pm) cut to y >= 0 (Sutherland–Hodgman against one half-plane).
void emit(MeshSliceScratch& s, std::int32_t id, BeamProfile& out) {
  auto& py = s.py;
  auto& pz = s.pz;
  auto& pm = s.pm;
  close_polygon(py, pz, pm);
  const std::size_t n = py.size();
  const bool all_in = std::all_of(py.begin(), py.end(), [](double y) { return y >= 0.0; });
  const double* ys = py.data();
  const double* zs = pz.data();
  const std::uint16_t* ms = pm.data();
  std::size_t count = n;
  if (!all_in) {
    s.cy.clear();
    s.cz.clear();
    s.cm.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = i + 1 < n ? i + 1 : 0;
      const bool in_i = py[i] >= 0.0, in_j = py[j] >= 0.0;
      if (in_i) push_node(s.cy, s.cz, s.cm, py[i], pz[i], pm[i]);
      if (in_i != in_j) {
        const double t = py[i] / (py[i] - py[j]);  // py[i] != py[j]: one is < 0, one >= 0
        push_node(s.cy, s.cz, s.cm, 0.0, pz[i] + t * (pz[j] - pz[i]), pm[i]);
      }
    }
    close_polygon(s.cy, s.cz, s.cm);
    ys = s.cy.data();
    zs = s.cz.data();
    ms = s.cm.data();
    count = s.cy.size();
  }
  if (count < 3) {
    if (n > 0 && all_in) ++s.dropped;
    return;
  }
  out.add_section(ys, zs, ms, count, id, ms[0]);
}

}  // namespace

void add_mesh_sections(const TriangleMesh& mesh, std::int32_t id, const Eigen::Vector2d& nadir_xy_m,
                       const Eigen::Vector2d& across_dir, BeamProfile& out, MeshSliceScratch& s) {
  mesh.triangles_near_plane(nadir_xy_m, across_dir, s.tris);
  // Signed distance to the plane along n = across x up = (a_y, -a_x); a vertex with d >= 0 is on
  // the positive side (a vertex on the plane counts as positive: every triangle is then cut
  // along exactly two edges or not at all, and its neighbours agree).
  const Eigen::Vector2d n(across_dir.y(), -across_dir.x());
  s.segs.clear();
  for (const std::uint32_t t : s.tris) {
    const auto& tri = mesh.triangle[t];
    double d[3], y[3];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& p = mesh.vertex_m[tri[static_cast<std::size_t>(k)]];
      const Eigen::Vector2d r(p.x() - nadir_xy_m.x(), p.y() - nadir_xy_m.y());
      d[k] = r.dot(n);
      y[k] = r.dot(across_dir);
    }
    MeshSliceScratch::Seg seg{};
    int found = 0;
    for (int k = 0; k < 3; ++k) {
      const int k2 = (k + 1) % 3;
      const bool pa = d[k] >= 0.0, pb = d[k2] >= 0.0;
      if (pa == pb) continue;
      // The crossing on edge (i, j), evaluated from the lower vertex index so that both
      // triangles sharing the edge get the same point.
      std::uint32_t i = tri[static_cast<std::size_t>(k)], j = tri[static_cast<std::size_t>(k2)];
      int ki = k, kj = k2;
      if (i > j) {
        std::swap(i, j);
        std::swap(ki, kj);
      }
      const double tt = d[ki] / (d[ki] - d[kj]);
      const double zi = mesh.vertex_m[i].z(), zj = mesh.vertex_m[j].z();
      const double cy = y[ki] + tt * (y[kj] - y[ki]), cz = zi + tt * (zj - zi);
      if (!pa) {  // negative -> positive along the winding: the segment's start A
        seg.ya = cy;
        seg.za = cz;
        seg.e_in = edge_key(i, j);
      } else {  // positive -> negative: its end B
        seg.yb = cy;
        seg.zb = cz;
        seg.e_out = edge_key(i, j);
      }
      ++found;
    }
    if (found != 2) continue;
    seg.mat = mesh.material[t];
    s.segs.push_back(seg);
  }
  const std::size_t m = s.segs.size();
  if (m == 0) return;
  // Chain: the segment after one ending on edge e is the one starting on e.
  s.by_in.clear();
  for (std::uint32_t i = 0; i < m; ++i) s.by_in.push_back({s.segs[i].e_in, i});
  std::sort(s.by_in.begin(), s.by_in.end());
  s.next.assign(m, -1);
  s.has_pred.assign(m, 0);
  s.visited.assign(m, 0);
  for (std::size_t i = 0; i < m; ++i) {
    const auto it = std::lower_bound(s.by_in.begin(), s.by_in.end(),
                                     std::pair<std::uint64_t, std::uint32_t>{s.segs[i].e_out, 0});
    if (it != s.by_in.end() && it->first == s.segs[i].e_out && it->second != i) {
      s.next[i] = it->second;
      s.has_pred[it->second] = 1;
    }
  }
  const auto walk = [&](std::size_t start) {
    s.py.clear();
    s.pz.clear();
    s.pm.clear();
    std::size_t k = start;
    bool closed = false;
    for (;;) {
      s.visited[k] = 1;
      const auto& g = s.segs[k];
      push_node(s.py, s.pz, s.pm, g.ya, g.za, g.mat);
      const std::int64_t nk = s.next[k];
      if (nk == static_cast<std::int64_t>(start)) {
        closed = true;
        break;
      }
      if (nk < 0 || s.visited[static_cast<std::size_t>(nk)]) break;
      k = static_cast<std::size_t>(nk);
    }
    if (!closed) {
      // An open chain: its end point, then back along itself (a thin two-sided surface).
      const auto& g = s.segs[k];
      push_node(s.py, s.pz, s.pm, g.yb, g.zb, g.mat);
      ++s.open_chains;
      if (s.py.size() == 2) {  // one straight piece: a midpoint makes it a polygon of 3+ nodes
        const double my = 0.5 * (s.py[0] + s.py[1]), mz = 0.5 * (s.pz[0] + s.pz[1]);
        s.py.insert(s.py.begin() + 1, my);
        s.pz.insert(s.pz.begin() + 1, mz);
        s.pm.insert(s.pm.begin() + 1, s.pm[0]);
      }
      const std::size_t len = s.py.size();
      if (len < 3) {
        ++s.dropped;
        return;
      }
      // Back from node len - 1 to node 1; node j's return facet (to node j - 1) has the
      // material of the forward facet j - 1 -> j.
      s.pm[len - 1] = s.pm[len - 2];
      for (std::size_t j = len - 1; j-- > 1;) {
        s.py.push_back(s.py[j]);
        s.pz.push_back(s.pz[j]);
        s.pm.push_back(s.pm[j - 1]);
      }
    }
    emit(s, id, out);
  };
  for (std::size_t i = 0; i < m; ++i) {
    if (!s.has_pred[i] && !s.visited[i]) walk(i);
  }
  for (std::size_t i = 0; i < m; ++i) {
    if (!s.visited[i]) walk(i);
  }
}

}  // namespace sonarsynth
