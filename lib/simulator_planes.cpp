// SPDX-License-Identifier: MIT
// The along-track beam planes of a ping side: their sum, the automatic plane count and the
// object window (docs/physics.md §1.3).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "sonarsynth/simulator.hpp"
#include "sonarsynth/simulator_state.hpp"

namespace sonarsynth {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The horizontal direction of the beam plane at azimuth psi from `across` (counter-clockwise).
Eigen::Vector2d plane_dir(const Eigen::Vector2d& across, double psi_rad) {
  const double c = std::cos(psi_rad), s = std::sin(psi_rad);
  return {c * across.x() - s * across.y(), s * across.x() + c * across.y()};
}

// The profile without its closed sections (the pilot pings of the seabed's plane count).
void strip_sections(BeamProfile& p) {
  p.section_y_m.clear();
  p.section_z_m.clear();
  p.section_start.clear();
  p.section_label.clear();
  p.section_material.clear();
  p.section_facet_material.clear();
}

// RMS over lit bins of |10 log10(a / b)|, in the bench's metric (docs/benchmarks.md): a bin is
// lit when either value exceeds 1e-3 x the median of the positive values of `b` on that side; a
// bin lit in one and below 1e-4 of the other counts as 40 dB.
class DbDifference {
 public:
  void add(const std::vector<double>& a, const std::vector<double>& b) {
    positive_.clear();
    for (const double v : b)
      if (v > 0.0) positive_.push_back(v);
    if (positive_.empty()) return;
    const auto mid = positive_.begin() + static_cast<std::ptrdiff_t>(positive_.size() / 2);
    std::nth_element(positive_.begin(), mid, positive_.end());
    const double lit = 1e-3 * *mid;
    for (std::size_t i = 0; i < a.size(); ++i) {
      const double x = a[i], y = b[i];
      if (!(x > lit || y > lit)) continue;
      const double d = x <= 1e-4 * y || y <= 1e-4 * x ? kCapDb : std::abs(10.0 * std::log10(x / y));
      sum_sq_ += d * d;
      ++bins_;
    }
  }
  bool empty() const { return bins_ == 0; }
  double rms_db() const {
    return bins_ > 0 ? std::sqrt(sum_sq_ / static_cast<double>(bins_)) : 0.0;
  }

 private:
  static constexpr double kCapDb = 40.0;
  std::vector<double> positive_;
  double sum_sq_ = 0.0;
  std::size_t bins_ = 0;
};

}  // namespace

AlongTrackChoice Simulator::choose_along_track_planes(const std::vector<PingPose>& pilot) const {
  const auto t0 = Clock::now();
  static constexpr int kLevels[] = {1, 3, 5, 9, 15};
  constexpr std::size_t kCount = sizeof(kLevels) / sizeof(kLevels[0]);
  const WorkspacePtr ws = make_workspace();
  // Noise-free energies of every pilot ping side at one plane count.
  auto energies = [&](int count) {
    const AlongTrackPlanes planes =
        make_along_track_planes(config_.sonar, count, cal_->side.beta_eff_rad);
    std::vector<std::vector<double>> e;
    for (const PingPose& pose : pilot) {
      for (const bool starboard : {false, true}) {
        render_planes(pose, starboard, planes, false, false, *ws, nullptr);
        e.push_back(ws->accum);
      }
    }
    return e;
  };
  // The fewest levels from kLevels[first] on within the tolerance of the next; the level index,
  // its estimate (NaN if none was made) and every estimate made.
  struct Level {
    std::size_t index = 0;
    double estimate_db = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> estimates_db;
  };
  auto choose = [&](std::size_t first, std::vector<std::vector<double>> coarse) {
    Level c;
    c.index = first;
    for (std::size_t j = first; j + 1 < kCount; ++j) {
      std::vector<std::vector<double>> fine = energies(kLevels[j + 1]);
      DbDifference diff;
      for (std::size_t i = 0; i < fine.size(); ++i) diff.add(coarse[i], fine[i]);
      c.estimate_db = diff.rms_db();
      c.estimates_db.push_back(c.estimate_db);
      c.index = j;
      if (c.estimate_db <= config_.quality.along_track_tolerance_db) break;
      c.index = j + 1;
      coarse = std::move(fine);
    }
    return c;
  };
  AlongTrackChoice choice;
  choice.automatic = true;
  // The seabed's count: the pilot profiles without their closed sections (objects that enter
  // the height profile, with solid_resting_objects off, stay in it).
  const bool objects = !scene_->objects.empty();
  ws->seabed_only = objects;
  std::vector<std::vector<double>> coarse = energies(kLevels[0]);
  const auto lit = [](const std::vector<double>& e) {
    return std::any_of(e.begin(), e.end(), [](double v) { return v > 0.0; });
  };
  for (std::size_t p = 0; p < pilot.size(); ++p) {
    if (lit(coarse[2 * p]) || lit(coarse[2 * p + 1])) ++choice.pilot_pings;
  }
  choice.planes = kLevels[0];
  choice.object_planes = kLevels[0];
  if (choice.pilot_pings > 0) {
    const Level seabed = choose(0, std::move(coarse));
    choice.planes = kLevels[seabed.index];
    choice.estimated_error_db = seabed.estimate_db;
    choice.estimates_db = seabed.estimates_db;
    choice.object_planes = choice.planes;
    if (objects) {
      // The objects' count, from the seabed's on (the objects add detail, never remove it).
      ws->seabed_only = false;
      const Level with = choose(seabed.index, energies(kLevels[seabed.index]));
      choice.object_planes = kLevels[with.index];
      choice.object_estimated_error_db = with.estimate_db;
    }
  } else {
    choice.estimated_error_db = 0.0;
  }
  choice.pilot_s = seconds_since(t0);
  return choice;
}

Simulator::SideGeometry Simulator::render_planes(const PingPose& pose, bool starboard,
                                                 const AlongTrackPlanes& run_planes, bool refine,
                                                 bool truth, Workspace& ws,
                                                 RenderTimings* timings) const {
  const std::size_t n = cal_->side.samples;
  const Eigen::Vector2d fwd(std::sin(pose.heading_rad), std::cos(pose.heading_rad));
  const Eigen::Vector2d stbd(fwd.y(), -fwd.x());
  const Eigen::Vector2d across = starboard ? stbd : Eigen::Vector2d(-stbd);
  SideGeometry geo;
  // Pitch tilts the beam plane: on a flat seabed its ground line moves along-track by
  // altitude * tan(pitch) (nose up -> ahead).
  const double alt = std::isfinite(pose.altitude_m) ? pose.altitude_m : 0.0;
  geo.nadir_xy_m = pose.sensor_xy_m + alt * std::tan(pose.pitch_rad) * fwd;
  geo.central_dir = across;
  // Roll (+ starboard down) depresses the starboard beam and raises the port one.
  ws.params.beam_axis_depression_rad =
      config_.sonar.tilt_rad + (starboard ? pose.roll_rad : -pose.roll_rad);
  const double max_y = config_.sonar.max_range_m;

  // Clock reads only when timings are requested.
  const auto now = [timings] { return timings != nullptr ? Clock::now() : Clock::time_point{}; };
  const AlongTrackPlanes& planes =
      refine && cal_->refiner &&
              cal_->refiner->refine(geo.nadir_xy_m, across, max_y, ws.refined, ws.refine_scratch)
          ? ws.refined
          : run_planes;
  const std::size_t count = planes.size();
  const std::size_t central = planes.central;
  // Object window: the object planes' profiles first (they may show an object the run planes
  // miss), the union of every profile's window (object_range_window), the run planes over the
  // whole side, then the object planes over the window only.
  const bool windowed = refine && &planes != &ws.refined && cal_->object_finder &&
                        cal_->object_finder->sees_object(geo.nadir_xy_m, across, max_y);
  double r_lo = std::numeric_limits<double>::infinity(), r_hi = -r_lo;
  const auto note_window = [&](const BeamProfile& p) {
    double lo = 0.0, hi = 0.0;
    if (!object_range_window(p, lo, hi)) return;
    r_lo = std::min(r_lo, lo);
    r_hi = std::max(r_hi, hi);
  };
  if (windowed) {
    const AlongTrackPlanes& op = cal_->object_planes;
    ws.object_profiles.resize(op.size());
    const auto t0 = now();
    for (std::size_t k = 0; k < op.size(); ++k) {
      if (k == shared_plane(planes)) continue;  // the run plane's profile
      build_beam_profile(*scene_, geo.nadir_xy_m, plane_dir(across, op.azimuth_rad[k]), max_y,
                         pose.sensor_z_m, config_.quality.profile, ws.object_profiles[k],
                         ws.scratch);
      note_window(ws.object_profiles[k]);
    }
    if (timings) timings->profile_s += seconds_since(t0);
  }
  if (timings != nullptr && &planes == &ws.refined) {
    ++timings->refined_sides;
    timings->refined_planes += count;
  }
  // A refined side renders every plane with truth: an object its central plane misses is
  // labelled where the planes that see it hold most of a sample's energy.
  const bool object_truth = truth && &planes == &ws.refined;
  if (object_truth) begin_object_truth(ws);
  // The central plane is rendered last, so its truth is what the echo holds afterwards.
  for (std::size_t idx = 0; idx < count; ++idx) {
    const std::size_t k = (idx + central + 1) % count;
    const Eigen::Vector2d dir = plane_dir(across, planes.azimuth_rad[k]);
    const auto t0 = now();
    build_beam_profile(*scene_, geo.nadir_xy_m, dir, max_y, pose.sensor_z_m,
                       config_.quality.profile, ws.profile, ws.scratch);
    if (ws.seabed_only) strip_sections(ws.profile);
    if (windowed) note_window(ws.profile);
    const auto t1 = now();
    ws.params.beta_eff_rad = planes.beta_eff_rad[k];
    ws.params.truth = truth && (k == central || object_truth);
    render_side(ws.profile, ws.params, ws.echo);
    if (object_truth) collect_object_truth(ws);
    if (timings) {
      timings->profile_s += std::chrono::duration<double>(t1 - t0).count();
      timings->render_s += seconds_since(t1);
    }
    // The first plane's intensity is taken over (0 + x == x; the echo's buffer is swapped, not
    // copied), later planes are added.
    if (idx == 0) {
      std::swap(ws.accum, ws.echo.intensity);
    } else {
      for (std::size_t i = 0; i < n; ++i) ws.accum[i] += ws.echo.intensity[i];
    }
    if (k == central) geo.central_dir = dir;
  }
  if (object_truth) apply_object_truth(ws);
  if (windowed && r_lo <= r_hi) render_object_window(r_lo, r_hi, ws, timings);
  return geo;
}

std::size_t Simulator::shared_plane(const AlongTrackPlanes& run_planes) const {
  const AlongTrackPlanes& op = cal_->object_planes;
  if (run_planes.size() != 1) return op.size();
  const auto it =
      std::find(op.azimuth_rad.begin(), op.azimuth_rad.end(), run_planes.azimuth_rad[0]);
  return static_cast<std::size_t>(it - op.azimuth_rad.begin());
}

void Simulator::render_object_window(double r_lo_m, double r_hi_m, Workspace& ws,
                                     RenderTimings* timings) const {
  const auto t0 = timings != nullptr ? Clock::now() : Clock::time_point{};
  const std::size_t n = cal_->side.samples;
  const double dr = cal_->side.sample_spacing_m;
  // Sample i integrates slant ranges within [(i + 1) dr - reach, (i + 1) dr] (render_side.hpp):
  // those meeting [r_lo, r_hi], with one sample to spare on each side.
  const double reach = std::max(cal_->side.pulse_window_m, dr);
  const double lo = std::floor(r_lo_m / dr) - 2.0;
  const double hi = std::floor((r_hi_m + reach) / dr) + 2.0;  // exclusive; +inf: to the end
  const std::size_t i0 = lo > 0.0 ? static_cast<std::size_t>(lo) : 0;
  const std::size_t i1 = hi < static_cast<double>(n) ? static_cast<std::size_t>(hi) : n;
  if (i0 >= i1) return;
  // Samples [0, i1) of a side of i1 samples are those of the whole side (the bins and every
  // sub-piece in them are the same), and facets nearer than render_from_m add nothing to
  // samples from i0 on, one sample to spare: the window is bit-identical to a full render.
  SideParams& p = ws.params;
  const std::size_t samples = p.samples;
  const bool truth = p.truth;
  p.samples = i1;
  p.truth = false;
  p.render_from_m = std::max(0.0, static_cast<double>(i0 + 1) * dr - reach - dr);
  const AlongTrackPlanes& op = cal_->object_planes;
  ws.window_accum.assign(i1 - i0, 0.0);
  const std::size_t shared = shared_plane(cal_->planes);
  for (std::size_t k = 0; k < op.size(); ++k) {
    if (k == shared) {
      // The intensity is linear in beta_eff: the run plane's, scaled to this plane's share.
      const double f = op.beta_eff_rad[k] / cal_->planes.beta_eff_rad[0];
      for (std::size_t i = i0; i < i1; ++i) ws.window_accum[i - i0] += f * ws.accum[i];
      continue;
    }
    p.beta_eff_rad = op.beta_eff_rad[k];
    render_side(ws.object_profiles[k], p, ws.window_echo);
    for (std::size_t i = i0; i < i1; ++i) ws.window_accum[i - i0] += ws.window_echo.intensity[i];
  }
  p.samples = samples;
  p.truth = truth;
  p.render_from_m = 0.0;
  std::copy(ws.window_accum.begin(), ws.window_accum.end(),
            ws.accum.begin() + static_cast<std::ptrdiff_t>(i0));
  if (timings) {
    ++timings->window_sides;
    timings->window_samples += i1 - i0;
    timings->render_s += seconds_since(t0);
  }
}

void Simulator::begin_object_truth(Workspace& ws) const {
  const std::size_t n = cal_->side.samples;
  ws.object_energy.assign(n, 0.0);
  ws.best_object_energy.assign(n, 0.0);
  SideEcho& b = ws.best_object;
  b.truth_label.assign(n, 0);
  b.truth_material.assign(n, 0);
  b.truth_grazing_rad.assign(cal_->side.truth_grazing ? n : 0, 0.0);
  b.truth_ground_y_m.assign(n, 0.0);
  b.truth_ground_z_m.assign(n, 0.0);
}

void Simulator::collect_object_truth(Workspace& ws) const {
  const SideEcho& e = ws.echo;
  SideEcho& b = ws.best_object;
  const bool grazing = !b.truth_grazing_rad.empty();
  for (std::size_t i = 0; i < e.intensity.size(); ++i) {
    if (e.truth_class[i] != SampleClass::object) continue;
    const double v = e.intensity[i];
    ws.object_energy[i] += v;
    if (v <= ws.best_object_energy[i]) continue;
    ws.best_object_energy[i] = v;
    b.truth_label[i] = e.truth_label[i];
    b.truth_material[i] = e.truth_material[i];
    if (grazing) b.truth_grazing_rad[i] = e.truth_grazing_rad[i];
    b.truth_ground_y_m[i] = e.truth_ground_y_m[i];
    b.truth_ground_z_m[i] = e.truth_ground_z_m[i];
  }
}

void Simulator::apply_object_truth(Workspace& ws) const {
  SideEcho& e = ws.echo;  // the central plane's truth
  const SideEcho& b = ws.best_object;
  const bool grazing = !b.truth_grazing_rad.empty();
  for (std::size_t i = 0; i < e.truth_class.size(); ++i) {
    if (e.truth_class[i] == SampleClass::object || !(ws.object_energy[i] > 0.5 * ws.accum[i]))
      continue;
    e.truth_class[i] = SampleClass::object;
    e.truth_label[i] = b.truth_label[i];
    e.truth_material[i] = b.truth_material[i];
    if (grazing) e.truth_grazing_rad[i] = b.truth_grazing_rad[i];
    e.truth_ground_y_m[i] = b.truth_ground_y_m[i];
    e.truth_ground_z_m[i] = b.truth_ground_z_m[i];
  }
}

}  // namespace sonarsynth
