// SPDX-License-Identifier: MIT
// Stability sweeps where rendering methods fail (docs/physics.md §2.5): per-bin error in dB
// and finiteness versus altitude (0.5-100 m, flat, closed form), across-track slope (0-89 deg
// towards and away, closed form with layover), grazing angle at far range (flat, absorption,
// closed form by Gauss-Legendre in incidence angle), DEM cell (0.02-2 m, the §2.5 sinusoid
// terrain against a 2 mm DEM) and object size (0.05-5 m rock on a flat seabed, 0.2 m ping
// spacing, against 31 along-track planes). Methods: exact clipping (2 and 1 Gauss points),
// sub-sampled profile (every 4th node), uniform-angle rays (10k, 100k), and for the object
// sweep along-track planes and the object rasterised into the DEM; objects as closed sections
// (clearance, size, grazing angle) in bench/stability_solids.cpp.
// Writes <out>/stability_<sweep>.csv.
//
// Usage: stability [--out DIR] [--tiny]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "analytic/flat_seabed.hpp"
#include "bench_main.hpp"
#include "bench_metrics.hpp"
#include "bench_render.hpp"
#include "bench_scenes.hpp"
#include "sonarsynth/bathy_gen.hpp"
#include "stability_solids.hpp"

namespace {

using namespace sonarsynth;
using namespace bench;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kMu = 0.01;
constexpr double kBeta = 0.0087;

using sonarsynth::analytic::flat_seabed_F;

SideParams base_params(double range_m, std::size_t samples) {
  SideParams p;
  p.sample_spacing_m = range_m / static_cast<double>(samples);
  p.samples = samples;
  p.beta_eff_rad = kBeta;
  p.vertical_beam.shape = VerticalBeamShape::uniform;
  p.materials = {Material{.name = "test"}};
  p.materials[0].lambert_mu = kMu;
  p.backscatter = BackscatterModel::lambert;
  return p;
}

std::vector<Method> profile_methods(bool tiny) {
  std::vector<Method> out;
  Method m = default_method();
  m.label = "exact";
  out.push_back(m);
  m.label = "exact+gauss=1";
  m.gauss_points = 1;
  out.push_back(m);
  m = default_method();
  m.family = "decimate";
  m.label = "decimate=4";
  m.decimate = 4;
  m.is_default = false;
  out.push_back(m);
  m = default_method();
  m.family = "rays";
  m.is_default = false;
  m.label = "rays=10000";
  m.rays = 10000;
  out.push_back(m);
  m.label = "rays=100000";
  m.rays = tiny ? 20000 : 100000;
  out.push_back(m);
  return out;
}

// Plane through the nadir point at height 0, slope s (> 0 rises towards the side), sampled
// every ds of arc length until the slant range exceeds r_max.
BeamProfile plane_profile(double h, double slope_rad, double r_max, double ds) {
  BeamProfile p;
  p.sensor_z_m = h;
  const double c = std::cos(slope_rad), s = std::sin(slope_rad);
  for (std::size_t i = 0;; ++i) {
    const double t = static_cast<double>(i) * ds;
    const double y = t * c, z = t * s;
    p.add_node(y, z);
    if (std::hypot(y, h - z) > r_max) break;
  }
  return p;
}

void row(std::FILE* f, const char* sweep, double x, const Method& m, const ErrorStats& e,
         double time_ms) {
  stability_row(f, sweep, x, m, e, time_ms);
}
constexpr const char* kHeader = kStabilityHeader;

// Renders `prof` with m, compares with ref, writes a row.
void compare(std::FILE* f, const char* sweep, double x, const Method& m, const BeamProfile& prof,
             const SideParams& p, const std::vector<double>& ref) {
  PingWorkspace ws;
  SideEcho e;
  SideParams q = p;
  q.gauss_points = m.gauss_points;
  const double t0 = now_s();
  render_profile(prof, q, m, ws, e);
  const double dt = now_s() - t0;
  ErrorStats s;
  s.add(e.intensity, ref, ref.size());
  row(f, sweep, x, m, s, 1e3 * dt);
}

void sweep_altitude(const std::string& dir, bool tiny) {
  std::FILE* f = open_csv(dir + "/stability_altitude.csv", kHeader);
  const SideParams p = base_params(150.0, 8192);
  for (const double h0 : {0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0}) {
    const double h = h0 + 0.003;
    std::vector<double> ref(p.samples);
    for (std::size_t i = 0; i < p.samples; ++i)
      ref[i] = kMu * kBeta / (h * h) *
               (flat_seabed_F(static_cast<double>(i + 1) * p.sample_spacing_m, h) -
                flat_seabed_F(static_cast<double>(i) * p.sample_spacing_m, h));
    const BeamProfile prof = plane_profile(h, 0.0, 151.0, 0.25);
    for (const Method& m : profile_methods(tiny)) compare(f, "altitude", h0, m, prof, p, ref);
  }
  std::fclose(f);
}

void sweep_slope(const std::string& dir, bool tiny) {
  std::FILE* f = open_csv(dir + "/stability_slope.csv", kHeader);
  const SideParams p = base_params(75.0, 4096);
  const double h = 10.003;
  for (const double deg : {-89.0, -80.0, -60.0, -45.0, -30.0, -15.0, -5.0, 0.0, 5.0, 15.0, 30.0,
                           45.0, 60.0, 80.0, 89.0}) {
    const double s = deg * kDeg;
    const double pp = h * std::cos(s);
    std::vector<double> ref(p.samples);
    for (std::size_t i = 0; i < p.samples; ++i) {
      const double r1 = static_cast<double>(i) * p.sample_spacing_m, r2 = r1 + p.sample_spacing_m;
      // Far branch from max(p, H if falling away) outward; rising: the near branch doubles
      // the bins between p and H (layover, §3.5).
      const double start = s > 0.0 ? pp : h;
      double e = flat_seabed_F(r2, pp) - flat_seabed_F(std::max(r1, start), pp);
      if (r2 <= start) e = 0.0;
      if (s > 0.0) e += flat_seabed_F(std::min(r2, h), pp) - flat_seabed_F(std::min(r1, h), pp);
      ref[i] = kMu * kBeta / (pp * pp) * std::max(0.0, e);
    }
    const BeamProfile prof = plane_profile(h, s, 76.0, 0.25);
    for (const Method& m : profile_methods(tiny)) compare(f, "slope", deg, m, prof, p, ref);
  }
  std::fclose(f);
}

// Flat bottom with absorption: E = (mu beta / H^2) int cos^3(phi) 10^(-2 alpha H/(10 cos phi))
// dphi over the bin's incidence interval, 5-point Gauss-Legendre on 4 panels.
void sweep_grazing(const std::string& dir, bool tiny) {
  std::FILE* f = open_csv(dir + "/stability_grazing.csv", kHeader);
  const double h = 5.003, range = 400.0;
  SideParams p = base_params(range, 16384);
  p.absorption_db_per_m = 0.1;
  const double x5[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                        0.9061798459386640};
  const double w5[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                        0.4786286704993665, 0.2369268850561891};
  std::vector<double> ref(p.samples, 0.0);
  for (std::size_t i = 0; i < p.samples; ++i) {
    const double r1 = std::max(h, static_cast<double>(i) * p.sample_spacing_m);
    const double r2 = static_cast<double>(i + 1) * p.sample_spacing_m;
    if (r2 <= h) continue;
    const double a = std::acos(h / r1), b = std::acos(h / r2);
    double sum = 0.0;
    for (int k = 0; k < 4; ++k) {
      const double lo = a + (b - a) * k / 4.0, hi = a + (b - a) * (k + 1) / 4.0;
      for (int g = 0; g < 5; ++g) {
        const double phi = 0.5 * (lo + hi) + 0.5 * (hi - lo) * x5[g];
        const double c = std::cos(phi);
        sum += 0.5 * (hi - lo) * w5[g] * c * c * c *
               std::pow(10.0, -2.0 * p.absorption_db_per_m * h / (10.0 * c));
      }
    }
    ref[i] = kMu * kBeta / (h * h) * sum;
  }
  const BeamProfile prof = plane_profile(h, 0.0, range + 1.0, 0.25);
  // Grazing-angle buckets (degrees) of the bin centres.
  const double edges[] = {0.5, 1.0, 2.0, 3.0, 5.0, 10.0, 20.0, 45.0, 90.0};
  for (const Method& m : profile_methods(tiny)) {
    PingWorkspace ws;
    SideEcho e;
    SideParams q = p;
    q.gauss_points = m.gauss_points;
    render_profile(prof, q, m, ws, e);
    for (std::size_t b = 0; b + 1 < std::size(edges); ++b) {
      std::vector<double> got_b, ref_b;
      for (std::size_t i = 0; i < p.samples; ++i) {
        const double r = (static_cast<double>(i) + 0.5) * p.sample_spacing_m;
        if (r <= h) continue;
        const double g = std::asin(h / r) / kDeg;
        if (g >= edges[b] && g < edges[b + 1]) {
          got_b.push_back(e.intensity[i]);
          ref_b.push_back(ref[i]);
        }
      }
      if (ref_b.empty()) continue;
      ErrorStats s;
      s.add(got_b, ref_b, ref_b.size());
      row(f, "grazing", std::sqrt(edges[b] * edges[b + 1]), m, s, 0.0);
    }
  }
  std::fclose(f);
}

double terrain_z(double y) {
  return 0.5 * std::sin(2.0 * kPi * y / 8.0) + 0.3 * std::sin(2.0 * kPi * y / 3.1);
}

BeamProfile terrain_profile(double h, double cell, double y_max) {
  BeamProfile p;
  p.sensor_z_m = h;
  const auto n = static_cast<std::size_t>(std::ceil(y_max / cell));
  for (std::size_t i = 0; i <= n; ++i) {
    const double y = static_cast<double>(i) * cell;
    p.add_node(y, terrain_z(y));
  }
  return p;
}

void sweep_dem(const std::string& dir, bool tiny) {
  std::FILE* f = open_csv(dir + "/stability_dem.csv", kHeader);
  SideParams p = base_params(75.0, 4096);
  const double h = 10.003;
  SideParams pr = p;
  pr.gauss_points = 5;
  SideEcho ref;
  render_side(terrain_profile(h, tiny ? 0.01 : 0.002, 76.0), pr, ref);
  for (const double cell : {0.02, 0.05, 0.1, 0.25, 0.5, 1.0, 2.0}) {
    const BeamProfile prof = terrain_profile(h, cell, 76.0);
    for (const Method& m : profile_methods(tiny))
      compare(f, "dem", cell, m, prof, p, ref.intensity);
  }
  std::fclose(f);
}

// A spherical rock of diameter d at 40 m ground range to starboard on a flat seabed (0.25 m
// DEM), pings every 0.2 m along-track over +-(d/2 + 1.5 m). Reference: analytic object,
// 31 along-track planes. Errors over the bins from 1 m before the object to the end of its
// shadow + 1 m, all pings.
void sweep_object(const std::string& dir, bool tiny) {
  std::FILE* f = open_csv(dir + "/stability_object.csv", kHeader);
  SimulationConfig cfg = bench_config(SceneKind::flat);
  const double h = 10.0;
  for (const double d : {0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0}) {
    Track tr;
    tr.start_xy_m = Eigen::Vector2d(-(0.5 * d + 1.5), 0.0);
    tr.spacing_m = 0.2;
    tr.pings = static_cast<int>(std::floor((d + 3.0) / 0.2)) + 1;
    tr.altitude_m = h;
    const Scene flat = make_scene(SceneKind::flat, 0.25, tr, "");
    ObjectPrimitive rock;
    rock.shape = ObjectShape::kEllipsoid;
    rock.id = 1;
    rock.centre_xy_m = Eigen::Vector2d(0.07, -40.0);  // starboard when heading east
    rock.half_extent_m = Eigen::Vector3d(0.5 * d, 0.5 * d, 0.5 * d);
    rock.place_on_seabed(flat.bathymetry, 0.0, 0.0, "rock");
    Scene with = make_scene(SceneKind::flat, 0.25, tr, "");
    with.objects.add(rock);
    with.objects.build_index();
    const std::vector<PingPose> poses = track_poses(with, tr);
    // The default quality chooses its along-track plane count from the sweep's pings.
    const Simulator sim(with, cfg, h, poses);
    std::printf("object %g m: default chose %d along-track plane(s), estimated error %.3f dB\n", d,
                sim.along_track().planes, sim.along_track().estimated_error_db);
    const SideParams& side = sim.side_params();
    const std::size_t n = side.samples;
    // Window of bins (starboard half) around the rock and its shadow.
    const double z_top = d, y_b = 40.0 + 0.5 * d;
    const double r0 = std::hypot(40.0 - 0.5 * d - 1.0, h);
    const double r1 = (d < h ? std::hypot(y_b, h - z_top) * h / (h - z_top) : 75.0) + 1.0;
    const auto i0 = n + static_cast<std::size_t>(r0 / side.sample_spacing_m);
    const auto i1 = n + std::min(n - 1, static_cast<std::size_t>(r1 / side.sample_spacing_m));
    Method ref_m = default_method();
    ref_m.along_track_planes = tiny ? 9 : 31;
    ref_m.profile.object_segments = 128;
    ref_m.gauss_points = 5;
    PingWorkspace ws;
    std::vector<std::vector<double>> ref(poses.size());
    for (std::size_t k = 0; k < poses.size(); ++k) {
      std::vector<double> full;
      render_ping_energy(with, side, cfg.sonar, poses[k], ref_m, ws, full);
      ref[k].assign(full.begin() + static_cast<std::ptrdiff_t>(i0),
                    full.begin() + static_cast<std::ptrdiff_t>(i1));
    }
    // Methods on the analytic object, and exact on the rock rasterised into DEMs.
    std::vector<std::pair<Method, const Scene*>> ms;
    Method m = default_method();
    m.label = "exact+planes=1";
    ms.push_back({m, &with});
    m.label = "exact+planes=5";
    m.is_default = false;
    m.along_track_planes = 5;
    ms.push_back({m, &with});
    m.label = "default (auto planes)";
    m.is_default = true;
    m.along_track_planes = sim.along_track().planes;
    ms.push_back({m, &with});
    m.is_default = false;
    m.family = "rays";
    m.label = "rays=30000";
    m.along_track_planes = 1;
    m.rays = 30000;
    ms.push_back({m, &with});
    std::vector<Scene> raster;
    raster.reserve(3);
    for (const double cell : {0.05, 0.25, 1.0}) {
      Scene s = make_scene(SceneKind::flat, cell, tr, "");
      auto& hz = s.bathymetry.mutable_heights();
      const GridGeometry& g = s.bathymetry.geometry();
      for (std::size_t r = 0; r < g.rows; ++r)
        for (std::size_t c = 0; c < g.cols; ++c) {
          const double top = with.objects.top_at(g.x_of_col(static_cast<double>(c)),
                                                 g.y_of_row(static_cast<double>(r)));
          if (top == top)
            hz[r * g.cols + c] = std::max(hz[r * g.cols + c], static_cast<float>(top));
        }
      raster.push_back(std::move(s));
      Method rm = default_method();
      rm.family = "dem";
      rm.is_default = false;
      rm.label = "dem-raster+cell=" + std::to_string(cell).substr(0, 4);
      ms.push_back({rm, &raster.back()});
    }
    for (const auto& [mm, sc] : ms) {
      ErrorStats s;
      double t = 0.0;
      for (std::size_t k = 0; k < poses.size(); ++k) {
        std::vector<double> full;
        const double t0 = now_s();
        render_ping_energy(*sc, side, cfg.sonar, poses[k], mm, ws, full);
        t += now_s() - t0;
        const std::vector<double> got(full.begin() + static_cast<std::ptrdiff_t>(i0),
                                      full.begin() + static_cast<std::ptrdiff_t>(i1));
        s.add(got, ref[k], got.size());
      }
      row(f, "object", d, mm, s, 1e3 * t / static_cast<double>(poses.size()));
    }
  }
  std::fclose(f);
}

int run(int argc, char** argv) {
  std::string out = ".";
  bool tiny = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (a == "--tiny") {
      tiny = true;
    } else {
      throw std::runtime_error("unknown argument " + a);
    }
  }
  sweep_altitude(out, tiny);
  sweep_slope(out, tiny);
  sweep_grazing(out, tiny);
  sweep_dem(out, tiny);
  sweep_object(out, tiny);
  sweep_solids(out, tiny);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main("stability", run, argc, argv);
}
