// SPDX-License-Identifier: MIT
// Speed vs accuracy of every quality knob of the renderer, of a sub-sampled profile and of
// uniform-angle ray casting, on (a) a flat seabed against the closed form (docs/physics.md
// §3.2), (b) a rough natural seabed and (c) the paper's pipe scene against a converged reference
// (exact clipping, 0.02 m DEM, 4 sub-segments per cell, 5 Gauss points, 15 along-track planes,
// 128 object segments). One thread; time per ping = both sides, profile extraction included,
// median of --runs runs, each of whole passes over the track's pings for at least --min-time
// seconds. Writes <out>/speed_accuracy_<scene>.csv and <out>/auto_planes_<scene>.csv (what the
// default's automatic along-track plane count chose).
//
// Pareto flags treat times within --time-tolerance (relative, default 5 %) of each other as
// equal (pareto_strict: plain dominance).
//
// Usage: speed_accuracy [--out DIR] [--pings N] [--runs R] [--min-time S] [--time-tolerance F]
//                       [--scenes flat,rough,paper] [--tiny] [--worst N] [--rays LIST]
//
// --rays LIST (e.g. 100000,300000,1000000@0.05) times only the default against uniform-angle
// ray casting with these rays per side (`@cell` renders the rays on a DEM of that cell, metres,
// and adds the default on that DEM), side by side in one run: the comparison at equal accuracy
// (docs/benchmarks.md).
//
// --worst N prints the default's N worst bins (error, ping, side, slant range, and the
// depression of that range over a flat seabed at the track altitude with its off-axis angle
// from the beam axis): where its error sits, e.g. at the edge of the paper beam.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "analytic/flat_seabed.hpp"
#include "bench_main.hpp"
#include "bench_metrics.hpp"
#include "bench_render.hpp"
#include "bench_scenes.hpp"

namespace {

using namespace sonarsynth;
using namespace bench;

using sonarsynth::analytic::flat_seabed_F;

struct RaySpec {
  std::size_t rays = 0;
  double cell_m = 0.0;  ///< 0 = the default's DEM
};

std::vector<Method> methods(bool tiny, int default_planes, const std::vector<RaySpec>& rays_only) {
  std::vector<Method> out;
  const Method d = default_method(default_planes);
  out.push_back(d);
  auto var = [&](const std::string& family, const std::string& label, auto&& edit) {
    Method m = d;
    m.family = family;
    m.label = label;
    m.is_default = false;
    edit(m);
    out.push_back(m);
  };
  if (!rays_only.empty()) {
    // The default on each finer DEM the rays use too: equal inputs, side by side.
    std::vector<double> cells;
    for (const RaySpec& r : rays_only) {
      if (r.cell_m > 0.0 && std::find(cells.begin(), cells.end(), r.cell_m) == cells.end()) {
        cells.push_back(r.cell_m);
        std::ostringstream l;
        l << "cell=" << r.cell_m;
        var("cell", l.str(), [&r](Method& m) { m.cell_m = r.cell_m; });
      }
    }
    for (const RaySpec& r : rays_only) {
      std::ostringstream l;
      l << "rays=" << r.rays;
      if (r.cell_m > 0.0) l << "+cell=" << r.cell_m;
      var("rays", l.str(), [&r](Method& m) {
        m.rays = r.rays;
        if (r.cell_m > 0.0) m.cell_m = r.cell_m;
      });
    }
    return out;
  }
  for (const int g : {1, 3, 5})
    var("gauss", "gauss=" + std::to_string(g), [g](Method& m) { m.gauss_points = g; });
  for (const int s : {2, 4, 8})
    var("subdiv", "subdiv=" + std::to_string(s),
        [s](Method& m) { m.profile.grid_subdivisions = s; });
  for (const int k : {1, 3, 5, 9, 15}) {
    if (k == default_planes) continue;
    var("planes", "planes=" + std::to_string(k), [k](Method& m) { m.along_track_planes = k; });
  }
  for (const int o : {4, 8, 32, 64})
    var("objseg", "objseg=" + std::to_string(o), [o](Method& m) { m.profile.object_segments = o; });
  for (const double c : {0.02, 0.05, 0.1, 0.5, 1.0, 2.0}) {
    std::ostringstream l;
    l << "cell=" << c;
    var("cell", l.str(), [c](Method& m) { m.cell_m = c; });
  }
  for (const int n : {2, 4, 8})
    var("decimate", "decimate=" + std::to_string(n), [n](Method& m) { m.decimate = n; });
  for (const std::size_t r : {1000u, 3000u, 10000u, 30000u, 100000u})
    var("rays", "rays=" + std::to_string(r), [r](Method& m) { m.rays = r; });
  var("rays", "rays=30000+cell=0.05", [](Method& m) {
    m.rays = 30000;
    m.cell_m = 0.05;
  });
  if (tiny) out.resize(4);
  return out;
}

// The default's `count` worst bins (see --worst in the header comment).
void print_worst(SceneKind kind, const std::vector<PingPose>& poses,
                 const std::vector<std::vector<double>>& ref, std::vector<double>& got,
                 const SideParams& side, const SimulationConfig& cfg, const Method& m,
                 const Scene& scene, std::size_t count) {
  const std::size_t n = side.samples;
  std::vector<BinError> worst;
  PingWorkspace ws;
  for (std::size_t p = 0; p < poses.size(); ++p) {
    render_ping_energy(scene, side, cfg.sonar, poses[p], m, ws, got);
    worst_bins(got, ref[p], n, count, p * 2 * n, worst);
  }
  constexpr double kDeg = 180.0 / 3.14159265358979323846;
  std::printf("%s: the default's %zu worst bins\n", to_string(kind), worst.size());
  for (const BinError& b : worst) {
    const std::size_t ping = b.index / (2 * n), bin = b.index % (2 * n);
    const std::size_t i = bin % n;
    const double r = (static_cast<double>(i) + 0.5) * side.sample_spacing_m;
    const double alt = poses[ping].altitude_m;
    const double dep = r > alt ? std::asin(alt / r) : 0.5 * 3.14159265358979323846;
    std::printf(
        "  %6.2f dB  ping %zu %s bin %zu  r %.3f m  depression %.2f deg  off-axis %.2f deg%s\n",
        b.error_db, ping, bin < n ? "port" : "stbd", i, r, dep * kDeg,
        (dep - cfg.sonar.tilt_rad) * kDeg, b.edge ? "  (edge)" : "");
  }
}

Method reference_method() {
  Method m;
  m.family = "reference";
  m.label = "reference";
  m.cell_m = 0.02;
  m.profile.grid_subdivisions = 4;
  m.profile.object_segments = 128;
  m.gauss_points = 5;
  m.along_track_planes = 15;
  return m;
}

// The exact energies of the flat seabed per ping and sample (port then starboard, 2 n).
void flat_reference(const Scene& base, const SideParams& side, std::size_t n,
                    std::vector<std::vector<double>>& ref) {
  const double coef = side.calibration_k *
                      backscatter_coefficient(side.backscatter,
                                              side.materials[base.material_map.default_material()]);
  const double h = kFlatAltitudeM, dr = side.sample_spacing_m;
  for (auto& r : ref) {
    r.assign(2 * n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const double e = coef * side.beta_eff_rad / (h * h) *
                       (flat_seabed_F(static_cast<double>(i + 1) * dr, h) -
                        flat_seabed_F(static_cast<double>(i) * dr, h));
      r[i] = r[n + i] = e;
    }
  }
}

// A method's errors over the track and its median time per ping.
struct Row {
  Method m;
  double time_ms;
  ErrorStats e;
};

// The time per ping of each row's method (seconds, one entry per run). Runs outer, methods
// inner, so that drifts of the machine load hit every method alike; each run starts at a
// different method (the first one timed after a switch of scene pays for cold caches; without
// the rotation that was always the default, ~10 % slower than identical settings).
std::vector<std::vector<double>> time_methods(const std::vector<Row>& rows, int runs,
                                              double min_time_s, auto& scene_at,
                                              const SideParams& side, const SimulationConfig& cfg,
                                              const std::vector<PingPose>& use_poses,
                                              PingWorkspace& ws) {
  std::vector<double> got;
  std::vector<std::vector<double>> times(rows.size());
  for (int r = 0; r < runs; ++r) {
    for (std::size_t j = 0; j < rows.size(); ++j) {
      const std::size_t i =
          (j + static_cast<std::size_t>(r) * rows.size() / static_cast<std::size_t>(runs)) %
          rows.size();
      const Scene& sc = scene_at(rows[i].m.cell_m);
      // Whole passes over the track until min_time has passed: a sample of a few milliseconds
      // is at the mercy of the scheduler.
      std::size_t rendered = 0;
      const double t0 = now_s();
      double elapsed = 0.0;
      do {
        for (const PingPose& pose : use_poses)
          render_ping_energy(sc, side, cfg.sonar, pose, rows[i].m, ws, got);
        rendered += use_poses.size();
        elapsed = now_s() - t0;
      } while (elapsed < min_time_s);
      times[i].push_back(elapsed / static_cast<double>(rendered));
    }
  }
  return times;
}

// Writes the rows with their Pareto flags to speed_accuracy_<scene>.csv in out_dir.
void write_rows_csv(SceneKind kind, const std::string& out_dir, const std::vector<Row>& rows,
                    const std::vector<bool>& front, const std::vector<bool>& strict,
                    const std::vector<double>& iqr_rel) {
  std::FILE* f = open_csv(out_dir + "/speed_accuracy_" + to_string(kind) + ".csv",
                          "scene,family,label,cell_m,subdiv,gauss,planes,objseg,decimate,rays,"
                          "time_ms,rms_db,worst_db,edge_rms_db,edge_worst_db,empty_frac,nonfinite,"
                          "pareto,default,bins,edge_bins,all_rms_db,pareto_strict,time_iqr_rel");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    std::fprintf(
        f,
        "%s,%s,%s,%g,%d,%d,%d,%d,%d,%zu,%.5g,%.5g,%.5g,%.5g,%.5g,%.5g,%zu,%d,%d,%zu,%zu,%.5g,%d,"
        "%.3g\n",
        to_string(kind), r.m.family.c_str(), r.m.label.c_str(), r.m.cell_m,
        r.m.profile.grid_subdivisions, r.m.gauss_points, r.m.along_track_planes,
        r.m.profile.object_segments, r.m.decimate, r.m.rays, r.time_ms, r.e.rms_db(), r.e.worst_db,
        r.e.edge_rms_db(), r.e.edge_worst_db, r.e.empty_fraction(), r.e.nonfinite, front[i] ? 1 : 0,
        r.m.is_default ? 1 : 0, r.e.bins, r.e.edge_bins, r.e.all_rms_db(), strict[i] ? 1 : 0,
        iqr_rel[i]);
  }
  std::fclose(f);
}

void run_scene(SceneKind kind, const std::string& out_dir, int pings, int runs, double min_time_s,
               double time_tolerance, bool tiny, std::size_t worst,
               const std::vector<RaySpec>& rays_only) {
  const std::string yaml = SONARSYNTH_SAMPLES_DIR "/paper_pipes.yaml";
  const Track track = track_for(kind, pings);
  std::map<double, Scene> scenes;
  auto scene_at = [&](double cell) -> const Scene& {
    auto it = scenes.find(cell);
    if (it == scenes.end()) it = scenes.emplace(cell, make_scene(kind, cell, track, yaml)).first;
    return it->second;
  };
  const SimulationConfig cfg = bench_config(kind);
  const Scene& base = scene_at(0.25);
  const std::vector<PingPose> poses = track_poses(base, track);
  // The default quality chooses its along-track plane count from pilot pings: here the track's.
  const Simulator sim(base, cfg, track.altitude_m, poses);
  const SideParams& side = sim.side_params();
  const std::size_t n = side.samples;
  const AlongTrackChoice& choice = sim.along_track();
  std::printf("%s: default chose %d along-track plane(s), estimated error %.3f dB, pilot %.1f ms\n",
              to_string(kind), choice.planes, choice.estimated_error_db, 1e3 * choice.pilot_s);
  {
    std::FILE* f = open_csv(out_dir + "/auto_planes_" + std::string(to_string(kind)) + ".csv",
                            "scene,planes,estimated_error_db,tolerance_db,pilot_pings,pilot_ms");
    std::fprintf(f, "%s,%d,%.5g,%.5g,%zu,%.5g\n", to_string(kind), choice.planes,
                 choice.estimated_error_db, cfg.quality.along_track_tolerance_db,
                 choice.pilot_pings, 1e3 * choice.pilot_s);
    std::fclose(f);
  }

  // Reference energies per ping.
  std::vector<std::vector<double>> ref(poses.size());
  PingWorkspace ws;
  if (kind == SceneKind::flat) {
    flat_reference(base, side, n, ref);
  } else {
    Method rm = reference_method();
    if (tiny) rm.cell_m = 0.1;
    const Scene& rs = scene_at(rm.cell_m);
    const std::vector<PingPose> rposes = track_poses(rs, track);
    const double t0 = now_s();
    for (std::size_t p = 0; p < poses.size(); ++p)
      render_ping_energy(rs, side, cfg.sonar, rposes[p], rm, ws, ref[p]);
    std::printf("%s: reference %.1f ms/ping\n", to_string(kind),
                1e3 * (now_s() - t0) / static_cast<double>(poses.size()));
  }

  // The same sensor positions for every method: heights from the reference DEM.
  const std::vector<PingPose> use_poses =
      kind == SceneKind::flat ? poses : track_poses(scene_at(tiny ? 0.1 : 0.02), track);
  std::vector<Row> rows;
  std::vector<double> got;
  for (const Method& m : methods(tiny, choice.planes, rays_only)) {
    const Scene& sc = scene_at(m.cell_m);
    Row row{m, 0.0, {}};
    for (std::size_t p = 0; p < use_poses.size(); ++p) {
      render_ping_energy(sc, side, cfg.sonar, use_poses[p], m, ws, got);
      row.e.add(got, ref[p], n);
    }
    rows.push_back(row);
    if (worst > 0 && m.is_default) print_worst(kind, use_poses, ref, got, side, cfg, m, sc, worst);
  }
  const std::vector<std::vector<double>> times =
      time_methods(rows, runs, min_time_s, scene_at, side, cfg, use_poses, ws);
  std::vector<double> x, y, iqr_rel;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    Row& row = rows[i];
    row.time_ms = 1e3 * median(times[i]);
    std::vector<double> t = times[i];
    std::sort(t.begin(), t.end());
    const auto at = [&t](double q) {
      return t[static_cast<std::size_t>(q * static_cast<double>(t.size() - 1) + 0.5)];
    };
    iqr_rel.push_back((at(0.75) - at(0.25)) / median(times[i]));
    std::printf(
        "%s %-22s %9.3f ms/ping  rms %7.3f dB  worst %7.2f dB  edge rms %6.2f  all rms "
        "%7.3f  empty %.3f\n",
        to_string(kind), row.m.label.c_str(), row.time_ms, row.e.rms_db(), row.e.worst_db,
        row.e.edge_rms_db(), row.e.all_rms_db(), row.e.empty_fraction());
    x.push_back(row.time_ms);
    y.push_back(row.e.all_rms_db());
  }
  const std::vector<bool> front = pareto_front(x, y, time_tolerance);
  const std::vector<bool> strict = pareto_front(x, y);
  write_rows_csv(kind, out_dir, rows, front, strict, iqr_rel);
}

int run(int argc, char** argv) {
  std::string out = ".";
  int pings = 10, runs = 15;
  double min_time_s = 0.03, time_tolerance = 0.05;
  bool tiny = false;
  std::size_t worst = 0;
  std::vector<SceneKind> kinds = {SceneKind::flat, SceneKind::rough, SceneKind::paper};
  std::vector<RaySpec> rays_only;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto next = [&] { return bench::value_after(i, argc, argv); };
    if (a == "--out") {
      out = next();
    } else if (a == "--pings") {
      pings = std::stoi(next());
    } else if (a == "--runs") {
      runs = std::stoi(next());
    } else if (a == "--min-time") {
      min_time_s = std::stod(next());
    } else if (a == "--time-tolerance") {
      time_tolerance = std::stod(next());
    } else if (a == "--tiny") {
      tiny = true;
      pings = 2;
      runs = 1;
      min_time_s = 0.0;
    } else if (a == "--worst") {
      worst = static_cast<std::size_t>(std::stoul(next()));
    } else if (a == "--scenes") {
      kinds.clear();
      std::stringstream ss(next());
      std::string tok;
      while (std::getline(ss, tok, ',')) kinds.push_back(parse_scene_kind(tok));
    } else if (a == "--rays") {
      std::stringstream ss(next());
      std::string tok;
      while (std::getline(ss, tok, ',')) {
        RaySpec r;
        const auto at = tok.find('@');
        r.rays = static_cast<std::size_t>(std::stoul(tok.substr(0, at)));
        if (at != std::string::npos) r.cell_m = std::stod(tok.substr(at + 1));
        if (r.rays == 0 || r.cell_m < 0.0) throw std::runtime_error("--rays: bad item " + tok);
        rays_only.push_back(r);
      }
    } else {
      throw std::runtime_error("unknown argument " + a);
    }
  }
  for (const SceneKind k : kinds)
    run_scene(k, out, pings, runs, min_time_s, time_tolerance, tiny, worst, rays_only);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main("speed_accuracy", run, argc, argv);
}
