// SPDX-License-Identifier: MIT
#include "sonarsynth/simulator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <thread>

#include "sonarsynth/error.hpp"
#include "sonarsynth/keyed_random.hpp"

namespace sonarsynth {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Keys of samples without a seabed contributor carry this bit so they never collide with
// ground-cell keys.
constexpr std::uint64_t kPingSampleKeyBit = 1ULL << 63;

std::uint64_t ping_sample_key(std::uint64_t ping, bool starboard, std::size_t sample) {
  return kPingSampleKeyBit | (hash_combine(hash_combine(ping, starboard ? 1 : 0), sample) >> 1);
}

}  // namespace

void QualityConfig::validate() const {
  profile.validate();
  if (gauss_points < 1 || gauss_points > 5) {
    throw InputError("quality: gauss_points = " + std::to_string(gauss_points) +
                     ". Violated constraint: 1 <= gauss_points <= 5");
  }
  if (along_track_planes < 1 || along_track_planes > 64) {
    throw InputError("quality: along_track_planes = " + std::to_string(along_track_planes) +
                     ". Violated constraint: 1 <= along_track_planes <= 64");
  }
}

void SimulationConfig::validate() const {
  sonar.validate();
  quality.validate();
  if (!(physics.calibration_k > 0.0) || !std::isfinite(physics.calibration_k)) {
    throw InputError("physics: calibration_k = " + std::to_string(physics.calibration_k) +
                     ". Violated constraint: calibration_k > 0");
  }
  if (physics.absorption) physics.water.validate();
  if (!(noise.paper_uniform_half_width >= 0.0 && noise.paper_uniform_half_width <= 1.0)) {
    throw InputError(
        "noise: uniform_half_width = " + std::to_string(noise.paper_uniform_half_width) +
        ". Violated constraint: 0 <= uniform_half_width <= 1");
  }
  if (!std::isfinite(noise.snr_at_max_range_db)) {
    throw InputError("noise: snr_db is not finite");
  }
  if (!(noise.freeze_cell_m >= 0.0)) {
    throw InputError("noise: freeze_cell_m = " + std::to_string(noise.freeze_cell_m) +
                     ". Violated constraint: freeze_cell_m >= 0");
  }
  if (!(output.max_value > 0.0)) {
    throw InputError("output: max_value = " + std::to_string(output.max_value) +
                     ". Violated constraint: max_value > 0");
  }
}

struct Simulator::Workspace {
  SideParams params;
  BeamProfile profile;
  ProfileScratch scratch;
  SideEcho echo;
  std::vector<double> accum;
  std::vector<std::uint64_t> keys;
  std::vector<std::uint64_t> noise_keys;
  std::vector<double> nu;
  std::vector<double> tvg_gain;  // linear TVG x quantiser gain per sample (precomputed)
};

Simulator::Simulator(const Scene& scene, const SimulationConfig& config,
                     double reference_altitude_m)
    : scene_(scene), config_(config) {
  config_.validate();
  if (scene.bathymetry.empty()) throw InputError("simulator: the scene has no bathymetry");
  const SonarConfig& s = config_.sonar;
  const PhysicsConfig& ph = config_.physics;
  alpha_db_per_m_ = ph.absorption ? francois_garrison_db_per_m(s.frequency_hz, ph.water) : 0.0;

  side_.sample_spacing_m = s.sample_spacing_m();
  side_.samples = s.samples_per_channel;
  side_.gauss_points = config_.quality.gauss_points;
  side_.shadows = ph.shadows;
  side_.beta_eff_rad = s.beta_eff_rad();
  side_.vertical_beam = ph.beam_pattern ? s.vertical_beam : VerticalBeamPattern{};
  side_.beam_axis_depression_rad = s.tilt_rad;
  side_.backscatter = ph.backscatter;
  side_.materials = scene.materials.all();
  side_.spreading = ph.spreading;
  side_.absorption_db_per_m = alpha_db_per_m_;
  side_.calibration_k = ph.calibration_k;
  side_.pulse_window_m = s.pulse_window_m() > s.sample_spacing_m() ? s.pulse_window_m() : 0.0;
  side_.truth = config_.truth || config_.noise.model == NoiseConfig::Model::kSpeckle;
  side_.validate();

  // Along-track planes: K azimuths across +-1.25 W, weighted by the two-way horizontal pattern,
  // sharing beta_eff exactly.
  const int k_planes = config_.quality.along_track_planes;
  if (k_planes == 1) {
    plane_psi_rad_ = {0.0};
    plane_beta_rad_ = {side_.beta_eff_rad};
  } else {
    const double span = 2.5 * s.horizontal_beam_width_rad;
    const double step = span / k_planes;
    double wsum = 0.0;
    for (int k = 0; k < k_planes; ++k) {
      const double psi = (k - 0.5 * (k_planes - 1)) * step;
      plane_psi_rad_.push_back(psi);
      plane_beta_rad_.push_back(s.horizontal_two_way(psi));
      wsum += plane_beta_rad_.back();
    }
    for (double& b : plane_beta_rad_) b *= side_.beta_eff_rad / wsum;
  }

  tvg_.law = config_.output.tvg;
  tvg_.absorption_db_per_m = alpha_db_per_m_;
  tvg_.validate();

  // Global calibration from a flat seabed of the default material at the reference altitude:
  // the gain (mid-range TVG'd mean -> max_value / 16) and the noise power (SNR at max range).
  BeamProfile flat;
  flat.sensor_z_m = reference_altitude_m;
  flat.add_node(0.0, 0.0, 0, scene.material_map.default_material());
  flat.add_node(s.max_range_m, 0.0, 0, scene.material_map.default_material());
  SideParams p = side_;
  p.truth = false;
  SideEcho echo;
  render_side(flat, p, echo);
  const std::size_t n = s.samples_per_channel;
  auto mean_over = [&](const std::vector<double>& v, double from, double to) {
    const auto i0 = std::min(n - 1, static_cast<std::size_t>(from * static_cast<double>(n)));
    const auto i1 = std::max(i0 + 1, static_cast<std::size_t>(to * static_cast<double>(n)));
    double sum = 0.0;
    for (std::size_t i = i0; i < std::min(i1, n); ++i) sum += v[i];
    return sum / static_cast<double>(std::min(i1, n) - i0);
  };
  const double far_raw = mean_over(echo.intensity, 0.9, 1.0);
  const double peak_raw = *std::max_element(echo.intensity.begin(), echo.intensity.end());
  const double snr = std::pow(10.0, config_.noise.snr_at_max_range_db / 10.0);
  noise_power_ = (far_raw > 0.0 ? far_raw : peak_raw) / snr;
  apply_tvg(tvg_, 0.5 * side_.sample_spacing_m, side_.sample_spacing_m, echo.intensity);
  const double mid = mean_over(echo.intensity, 0.45, 0.55);
  quantizer_.max_value = config_.output.max_value;
  quantizer_.round_to_integer = config_.output.round_to_integer;
  quantizer_.gain_db = config_.output.gain_db;
  if (std::isnan(quantizer_.gain_db)) {
    quantizer_.gain_db = mid > 0.0 ? 10.0 * std::log10(config_.output.max_value / 16.0 / mid) : 0.0;
  }
  quantizer_.validate();
}

Simulator::~Simulator() = default;

void Simulator::WorkspaceDeleter::operator()(Workspace* ws) const {
  delete ws;
}

Simulator::WorkspacePtr Simulator::make_workspace() const {
  WorkspacePtr ws(new Workspace());
  ws->params = side_;
  // TVG and quantiser gain per sample, once: the noise stage then costs one multiply.
  ws->tvg_gain.assign(side_.samples, 1.0);
  apply_tvg(tvg_, 0.5 * side_.sample_spacing_m, side_.sample_spacing_m, ws->tvg_gain);
  const double g = std::pow(10.0, quantizer_.gain_db / 10.0);
  for (double& v : ws->tvg_gain) v *= g;
  return ws;
}

void Simulator::render_side_output(const PingPose& pose, bool starboard, Workspace& ws,
                                   SideOutput& out, RenderTimings* timings) const {
  const std::size_t n = side_.samples;
  const Eigen::Vector2d fwd(std::sin(pose.heading_rad), std::cos(pose.heading_rad));
  const Eigen::Vector2d stbd(fwd.y(), -fwd.x());
  const Eigen::Vector2d across = starboard ? stbd : Eigen::Vector2d(-stbd);
  // Pitch tilts the beam plane: on a flat seabed its ground line moves along-track by
  // altitude * tan(pitch) (nose up -> ahead).
  const double alt = std::isfinite(pose.altitude_m) ? pose.altitude_m : 0.0;
  const Eigen::Vector2d nadir = pose.sensor_xy_m + alt * std::tan(pose.pitch_rad) * fwd;
  // Roll (+ starboard down) depresses the starboard beam and raises the port one.
  ws.params.beam_axis_depression_rad =
      config_.sonar.tilt_rad + (starboard ? pose.roll_rad : -pose.roll_rad);
  const double max_y = config_.sonar.max_range_m;

  ws.accum.assign(n, 0.0);
  const std::size_t central = plane_psi_rad_.size() / 2;
  Eigen::Vector2d central_dir = across;
  bool have_truth = false;
  for (std::size_t k = 0; k < plane_psi_rad_.size(); ++k) {
    const double c = std::cos(plane_psi_rad_[k]), s = std::sin(plane_psi_rad_[k]);
    const Eigen::Vector2d dir(c * across.x() - s * across.y(), s * across.x() + c * across.y());
    auto t0 = Clock::now();
    build_beam_profile(scene_, nadir, dir, max_y, pose.sensor_z_m, config_.quality.profile,
                       ws.profile, ws.scratch);
    auto t1 = Clock::now();
    ws.params.beta_eff_rad = plane_beta_rad_[k];
    ws.params.truth = side_.truth && k == central;
    render_side(ws.profile, ws.params, ws.echo);
    if (timings) {
      timings->profile_s += std::chrono::duration<double>(t1 - t0).count();
      timings->render_s += seconds_since(t1);
    }
    for (std::size_t i = 0; i < n; ++i) ws.accum[i] += ws.echo.intensity[i];
    if (k == central) {
      central_dir = dir;
      have_truth = ws.params.truth;
    }
  }

  const auto t2 = Clock::now();
  const SideEcho& e = ws.echo;  // truth of the central plane (rendered last among truth planes)
  // The echo's truth arrays hold the central plane only if it was rendered last with truth on;
  // with K > 1 planes the central one is not last, so re-render it for truth when needed.
  if (have_truth && central + 1 != plane_psi_rad_.size()) {
    build_beam_profile(scene_, nadir, central_dir, max_y, pose.sensor_z_m, config_.quality.profile,
                       ws.profile, ws.scratch);
    ws.params.beta_eff_rad = plane_beta_rad_[central];
    ws.params.truth = true;
    render_side(ws.profile, ws.params, ws.echo);
  }

  const NoiseConfig& nc = config_.noise;
  const std::uint64_t ping = pose.ping_index;
  if (nc.model != NoiseConfig::Model::kNone) {
    ws.noise_keys.resize(n);
    for (std::size_t i = 0; i < n; ++i) ws.noise_keys[i] = ping_sample_key(ping, starboard, i);
  }
  if (nc.model == NoiseConfig::Model::kPaper) {
    PaperNoise pn;
    pn.uniform_half_width = nc.paper_uniform_half_width;
    pn.rayleigh_sigma = std::sqrt(noise_power_ / 2.0);  // Rayleigh mean power 2 sigma^2 = N
    pn.seed = config_.seed;
    apply_paper_noise(pn, ws.noise_keys, ws.accum);
  } else if (nc.model == NoiseConfig::Model::kSpeckle) {
    // Frozen speckle: the key of a sample is the seabed cell of its dominant contributor.
    const double cell =
        nc.freeze_cell_m > 0 ? nc.freeze_cell_m : config_.sonar.range_resolution_m();
    ws.keys.resize(n);
    ws.nu.assign(nc.texture ? n : 0, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const SampleClass cls = e.truth_class[i];
      if (cls == SampleClass::seabed || cls == SampleClass::object) {
        const Eigen::Vector2d g = nadir + e.truth_ground_y_m[i] * central_dir;
        const auto ix = static_cast<std::int64_t>(std::floor(g.x() / cell));
        const auto iy = static_cast<std::int64_t>(std::floor(g.y() / cell));
        const auto iz = static_cast<std::int64_t>(std::floor(e.truth_ground_z_m[i] / cell));
        ws.keys[i] = ~kPingSampleKeyBit & hash_combine(hash_combine(static_cast<std::uint64_t>(ix),
                                                                    static_cast<std::uint64_t>(iy)),
                                                       static_cast<std::uint64_t>(iz));
        if (nc.texture) ws.nu[i] = side_.materials[e.truth_material[i]].texture_shape_nu;
      } else {
        ws.keys[i] = ws.noise_keys[i];
      }
    }
    SpeckleNoise sn;
    sn.thermal_noise_power = noise_power_;
    sn.seed = config_.seed;
    apply_speckle_noise(sn, ws.keys, ws.noise_keys, ws.nu, ws.accum);
  }

  // TVG and quantisation (precomputed per-sample gain).
  out.samples.resize(n);
  const double maxv = quantizer_.max_value;
  for (std::size_t i = 0; i < n; ++i) {
    double v = ws.accum[i] * ws.tvg_gain[i];
    v = std::isfinite(v) ? std::clamp(v, 0.0, maxv) : 0.0;
    out.samples[i] = static_cast<float>(quantizer_.round_to_integer ? std::round(v) : v);
  }

  if (config_.truth) {
    out.truth_class.assign(e.truth_class.begin(), e.truth_class.end());
    out.truth_label.assign(e.truth_label.begin(), e.truth_label.end());
    out.truth_grazing_rad.resize(n);
    out.truth_ground_x_m.resize(n);
    out.truth_ground_y_m.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      out.truth_grazing_rad[i] = static_cast<float>(e.truth_grazing_rad[i]);
      const Eigen::Vector2d g = nadir + e.truth_ground_y_m[i] * central_dir;  // NaN stays NaN
      out.truth_ground_x_m[i] = g.x();
      out.truth_ground_y_m[i] = g.y();
    }
  }
  if (timings) timings->noise_s += seconds_since(t2);
}

void Simulator::render_ping(const PingPose& pose, Workspace& ws, RenderedPing& out,
                            RenderTimings* timings) const {
  out.pose = pose;
  render_side_output(pose, false, ws, out.port, timings);
  render_side_output(pose, true, ws, out.starboard, timings);
}

RenderTimings Simulator::run(
    const Survey& survey, PingSink& sink,
    const std::function<void(std::uint64_t, std::uint64_t)>& progress) const {
  const unsigned threads =
      config_.threads > 0 ? config_.threads : std::max(1u, std::thread::hardware_concurrency());
  const std::uint64_t total = survey.total_pings();
  const std::uint64_t block = 16ULL * threads;
  std::vector<WorkspacePtr> workspaces;
  std::vector<RenderTimings> timings(threads);
  for (unsigned t = 0; t < threads; ++t) workspaces.push_back(make_workspace());
  std::vector<RenderedPing> pings(block);
  std::size_t current_line = static_cast<std::size_t>(-1);
  for (std::uint64_t first = 0; first < total; first += block) {
    const std::uint64_t count = std::min(block, total - first);
    // Static round-robin partition: ping first + i goes to thread i % threads. Every ping is a
    // pure function of its index, so the result is the same for any thread count.
    std::vector<std::exception_ptr> errors(threads);
    auto work = [&](unsigned t) {
      try {
        for (std::uint64_t i = t; i < count; i += threads) {
          render_ping(survey.pose(first + i, scene_.bathymetry), *workspaces[t], pings[i],
                      &timings[t]);
        }
      } catch (...) {
        errors[t] = std::current_exception();
      }
    };
    if (threads == 1) {
      work(0);
    } else {
      std::vector<std::jthread> pool;
      for (unsigned t = 0; t < threads; ++t) pool.emplace_back(work, t);
    }
    for (auto& e : errors) {
      if (e) std::rethrow_exception(e);
    }
    for (std::uint64_t i = 0; i < count; ++i) {
      const std::size_t line = pings[i].pose.line;
      if (line != current_line) {
        if (current_line != static_cast<std::size_t>(-1)) sink.end_line(current_line);
        sink.begin_line(line);
        current_line = line;
      }
      sink.ping(pings[i]);
    }
    if (progress) progress(first + count, total);
  }
  if (current_line != static_cast<std::size_t>(-1)) sink.end_line(current_line);
  RenderTimings sum;
  for (const auto& t : timings) {
    sum.profile_s += t.profile_s;
    sum.render_s += t.render_s;
    sum.noise_s += t.noise_s;
  }
  return sum;
}

}  // namespace sonarsynth
