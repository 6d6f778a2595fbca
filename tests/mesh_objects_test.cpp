// SPDX-License-Identifier: MIT
// Mesh objects (docs/physics.md §2.1, docs/scene-format.md "mesh"): a mesh cube renders as the
// analytic box, a mesh cylinder converges to the analytic cylinder as its ring is refined, and
// degenerate or non-manifold meshes give finite echoes.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <vector>

#include "object_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/render_side.hpp"
#include "sonarsynth/scene.hpp"
#include "sonarsynth/scene_profile.hpp"

namespace sonarsynth {
namespace {

constexpr double kPiT = 3.14159265358979323846;

Scene flat_scene() {
  return test::flat_scene(0.5, 20.0);
}

// Orients every triangle of a convex model outward (its normal away from `inside`).
void orient_outward(TriangleMesh& m, const Eigen::Vector3d& inside) {
  for (auto& t : m.triangle) {
    const Eigen::Vector3d &a = m.vertex_m[t[0]], &b = m.vertex_m[t[1]], &c = m.vertex_m[t[2]];
    if ((b - a).cross(c - a).dot((a + b + c) / 3.0 - inside) < 0.0) std::swap(t[1], t[2]);
  }
}

// A box [-hx, hx] x [-hy, hy] x [0, 2 hz] as 12 triangles.
TriangleMesh box_mesh(double hx, double hy, double hz, std::uint16_t mat) {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k) {
    m.vertex_m.push_back({(k & 1) ? hx : -hx, (k & 2) ? hy : -hy, (k & 4) ? 2.0 * hz : 0.0});
  }
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    const auto u = [&](int i) { return static_cast<std::uint32_t>(f[i]); };
    m.triangle.push_back({u(0), u(1), u(2)});
    m.triangle.push_back({u(0), u(2), u(3)});
  }
  m.material.assign(m.triangle.size(), mat);
  orient_outward(m, {0.0, 0.0, hz});
  return m;
}

// A closed cylinder along model x (length 2 hl, radius r, lowest point z = 0), n ring nodes.
TriangleMesh cylinder_mesh(double hl, double r, int n, std::uint16_t mat) {
  TriangleMesh m;
  for (const double x : {-hl, hl}) {
    for (int k = 0; k < n; ++k) {
      const double a = 2.0 * kPiT * k / n;
      m.vertex_m.push_back({x, r * std::cos(a), r + r * std::sin(a)});
    }
    m.vertex_m.push_back({x, 0.0, r});  // cap centre
  }
  const auto n1 = static_cast<std::uint32_t>(n + 1);
  for (std::uint32_t k = 0; k < static_cast<std::uint32_t>(n); ++k) {
    const std::uint32_t k2 = (k + 1) % static_cast<std::uint32_t>(n);
    m.triangle.push_back({k, k2, n1 + k});
    m.triangle.push_back({k2, n1 + k2, n1 + k});
    m.triangle.push_back({k, k2, n1 - 1});
    m.triangle.push_back({n1 + k, n1 + k2, 2 * n1 - 1});
  }
  m.material.assign(m.triangle.size(), mat);
  orient_outward(m, {0.0, 0.0, r});
  return m;
}

SideParams params(const Scene& scene, std::size_t samples) {
  SideParams p;
  p.sample_spacing_m = 0.05;
  p.samples = samples;
  p.beta_eff_rad = 0.02;
  p.vertical_beam.shape = VerticalBeamShape::uniform;
  p.materials = scene.materials.all();
  p.backscatter = BackscatterModel::lambert;
  p.truth = true;
  return p;
}

std::vector<double> render(const Scene& scene, const Eigen::Vector2d& nadir,
                           const Eigen::Vector2d& across, const ProfileOptions& opt = {},
                           std::size_t* sections = nullptr) {
  BeamProfile prof;
  ProfileScratch scratch;
  build_beam_profile(scene, nadir, across, 40.0, -10.0, opt, prof, scratch);
  if (sections) *sections = prof.sections();
  SideEcho e;
  render_side(prof, params(scene, 900), e);
  return e.intensity;
}

Scene with(const Scene& base, const ObjectPrimitive& o) {
  Scene s = base;
  s.objects = ObjectSet{};
  s.objects.add(o);
  s.objects.build_index();
  return s;
}

TEST(MeshObjects, MeshCubeRendersAsTheAnalyticBox) {
  Scene base = flat_scene();
  // Smooth steel: the built-in roughness subdivides the two sections differently.
  Material smooth = base.materials[base.materials.index_of("steel")];
  smooth.roughness_rms_m = 0.0;
  const std::uint16_t steel = base.materials.set(smooth);
  for (const double clearance : {0.0, 0.7}) {
    for (const double heading_deg : {0.0, 30.0, 90.0}) {
      ObjectPrimitive box;
      box.shape = ObjectShape::kBox;
      box.id = 4;
      box.material = steel;
      box.centre_xy_m = {14.0, 2.0};
      box.heading_rad = heading_deg * kPiT / 180.0;
      box.half_extent_m = {2.5, 1.0, 0.75};
      box.place_on_seabed(base.bathymetry, clearance, 0.0, "box");
      MeshPlacement where;
      where.position_xy_m = box.centre_xy_m;
      where.heading_rad = box.heading_rad;
      where.clearance_m = clearance;
      const ObjectPrimitive mesh =
          place_mesh(box_mesh(2.5, 1.0, 0.75, steel), where, base.bathymetry, 4, steel, "cube");
      const Scene a = with(base, box), b = with(base, mesh);
      std::size_t planes = 0;
      for (const double y0 : {-1.5, 0.0, 1.3, 1.7, 2.2, 2.9, 4.0}) {
        for (const double turn_deg : {0.0, 7.0, -20.0}) {
          const double t = turn_deg * kPiT / 180.0;
          const Eigen::Vector2d nadir(0.0, y0), across(std::cos(t), std::sin(t));
          std::size_t sa = 0, sb = 0;
          const auto ea = render(a, nadir, across, {}, &sa);
          const auto eb = render(b, nadir, across, {}, &sb);
          EXPECT_EQ(sa, sb) << clearance << " " << heading_deg << " " << y0 << " " << turn_deg;
          if (sa > 0) ++planes;
          ASSERT_EQ(ea.size(), eb.size());
          for (std::size_t i = 0; i < ea.size(); ++i) {
            ASSERT_NEAR(eb[i], ea[i], 1e-9 * std::abs(ea[i]) + 1e-300)
                << "bin " << i << " clearance " << clearance << " heading " << heading_deg << " y0 "
                << y0 << " turn " << turn_deg;
          }
        }
      }
      EXPECT_GT(planes, 5u);  // the rays do cross the box
    }
  }
}

TEST(MeshObjects, MeshCylinderConvergesToTheAnalyticCylinder) {
  // A pipe 0.5 m in radius, 1 m above the seabed, across the ray: the analytic section with 256
  // segments is the reference; the mesh's inscribed ring converges to it as n^-2.
  const Scene base = flat_scene();
  const std::uint16_t steel = base.materials.index_of("steel");
  ObjectPrimitive pipe;
  pipe.shape = ObjectShape::kCylinder;
  pipe.id = 2;
  pipe.material = steel;
  pipe.centre_xy_m = {15.0, 0.0};
  pipe.half_extent_m = {10.0, 0.5, 0.5};
  pipe.place_on_seabed(base.bathymetry, 1.0, 0.0, "pipe");
  pipe.base_z_m = {pipe.base_z_m.front()};
  pipe.base_step_m = 0.0;
  ProfileOptions fine;
  fine.object_segments = 256;
  const auto ref = render(with(base, pipe), {0.0, 0.0}, {1.0, 0.0}, fine);
  double total = 0.0;
  for (const double v : ref) total += v;
  ASSERT_GT(total, 0.0);
  double last = 1.0, first = 0.0;
  for (const int n : {8, 16, 32, 64, 128}) {
    MeshPlacement where;
    where.position_xy_m = pipe.centre_xy_m;
    where.clearance_m = 1.0;
    const auto m = place_mesh(cylinder_mesh(10.0, 0.5, n, steel), where, base.bathymetry, 2, steel,
                              "cylinder");
    const auto e = render(with(base, m), {0.0, 0.0}, {1.0, 0.0});
    double err = 0.0;
    for (std::size_t i = 0; i < e.size(); ++i) {
      ASSERT_TRUE(std::isfinite(e[i]));
      err += std::abs(e[i] - ref[i]);
    }
    err /= total;
    EXPECT_LT(err, 0.8 * last) << n;  // ~4x per doubling for n^-2 (the bins at shadow edges less)
    if (n == 8) first = err;
    last = err;
  }
  EXPECT_LT(last, first / 50.0);
  EXPECT_LT(last, 2e-3);
}

TEST(MeshObjects, DegenerateAndNonManifoldMeshesStayFinite) {
  const Scene base = flat_scene();
  const std::uint16_t steel = base.materials.index_of("steel");
  TriangleMesh m = box_mesh(1.0, 1.0, 1.0, steel);
  const auto nv = static_cast<std::uint32_t>(m.vertex_m.size());
  m.vertex_m.push_back({0.0, 3.0, 0.5});  // a fin on an edge of the box: a non-manifold edge
  m.vertex_m.push_back({0.0, 0.0, 1.0});  // collinear with vertices 4 and 7's edge midpoint
  m.vertex_m.push_back({3.0, 0.0, 3.0});  // an open sheet
  m.vertex_m.push_back({3.0, 2.0, 3.0});
  m.vertex_m.push_back({4.0, 1.0, 3.5});
  m.triangle.push_back({3, 7, nv});                // non-manifold: a third triangle on edge 3-7
  m.triangle.push_back({5, 5, 6});                 // repeated index
  m.triangle.push_back({4, nv + 1, 7});            // zero area (collinear)
  m.triangle.push_back({0, 1, 3});                 // a duplicate of a box face triangle
  m.triangle.push_back({3, 1, 0});                 // and it flipped
  m.triangle.push_back({nv + 2, nv + 3, nv + 4});  // a lone triangle
  m.material.resize(m.triangle.size(), steel);
  MeshPlacement where;
  where.position_xy_m = {12.0, 0.0};
  const Scene s = with(base, place_mesh(m, where, base.bathymetry, 7, steel, "odd"));
  ProfileScratch scratch;
  std::size_t lit_planes = 0;
  for (int k = -40; k <= 40; ++k) {
    // Rays through vertices, along edges and across faces (every 0.1 m and a few angles).
    for (const double turn_deg : {0.0, 45.0, 90.0}) {
      const double t = turn_deg * kPiT / 180.0;
      const Eigen::Vector2d across(std::cos(t), std::sin(t));
      const Eigen::Vector2d perp(-across.y(), across.x());
      const Eigen::Vector2d nadir = Eigen::Vector2d(12.0, 0.0) - 12.0 * across + 0.1 * k * perp;
      BeamProfile prof;
      build_beam_profile(s, nadir, across, 40.0, -10.0, {}, prof, scratch);
      for (double v : prof.section_y_m) ASSERT_TRUE(std::isfinite(v) && v >= 0.0);
      for (double v : prof.section_z_m) ASSERT_TRUE(std::isfinite(v));
      SideEcho e;
      render_side(prof, params(s, 900), e);  // validates the profile
      double sum = 0.0;
      for (const double v : e.intensity) {
        ASSERT_TRUE(std::isfinite(v) && v >= 0.0);
        sum += v;
      }
      EXPECT_GT(sum, 0.0);
      if (prof.sections() > 0) ++lit_planes;
    }
  }
  EXPECT_GT(lit_planes, 50u);
  EXPECT_GT(scratch.mesh.open_chains, 0u);  // the fin and the lone triangle: thin surfaces
}

TEST(MeshObjects, BadModelsAndPlacementsAreNamed) {
  const Scene base = flat_scene();
  const auto fails = [&](TriangleMesh m, MeshPlacement w, const std::string& what) {
    try {
      place_mesh(std::move(m), w, base.bathymetry, 1, 0, "wreck.obj");
      ADD_FAILURE() << "accepted: " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("wreck.obj"), std::string::npos) << e.what();
    }
  };
  MeshPlacement ok;
  fails(TriangleMesh{}, ok, "no triangles");
  TriangleMesh bad = box_mesh(1, 1, 1, 0);
  bad.triangle[3][1] = 99;
  fails(bad, ok, "names vertex 99");
  MeshPlacement neg = ok;
  neg.scale = {1.0, -1.0, 1.0};
  fails(box_mesh(1, 1, 1, 0), neg, "scale");
  MeshPlacement far = ok;
  far.position_xy_m = {60.0, 0.0};
  fails(box_mesh(1, 1, 1, 0), far, "outside the bathymetry grid");
}

}  // namespace
}  // namespace sonarsynth
