// SPDX-License-Identifier: MIT
#include "sonarsynth/simulator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "sonarsynth/along_track_planes.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/noise.hpp"
#include "sonarsynth/render_side.hpp"
#include "sonarsynth/sample_keys.hpp"
#include "sonarsynth/scene_profile.hpp"
#include "sonarsynth/sensor_effects.hpp"
#include "sonarsynth/sensor_kernel.hpp"
#include "sonarsynth/simulator_state.hpp"
#include "sonarsynth/tvg.hpp"

namespace sonarsynth {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Key of (ping, side, sample) = bit | hash_combine(hash_combine(ping, side), sample) >> 1, with
// the (ping, side) part hoisted out of the loop and splitmix64(sample) precomputed:
// hash_combine(h, i) = splitmix64(h ^ splitmix64(i)) (same values as the nested form).
void ping_sample_keys(std::uint64_t ping, bool starboard, const std::vector<std::uint64_t>& sh,
                      std::vector<std::uint64_t>& keys) {
  keys.resize(sh.size());
  sample_keys::ping_keys(hash_combine(ping, starboard ? 1 : 0), sh.data(), sh.size(), keys.data());
}

// The per-side renderer parameters of `config` (SideParams), absorption alpha_db_per_m.
SideParams side_params_of(const SimulationConfig& config, const Scene& scene,
                          double alpha_db_per_m) {
  const SonarConfig& s = config.sonar;
  const PhysicsConfig& ph = config.physics;
  SideParams side;
  side.sample_spacing_m = s.sample_spacing_m();
  side.samples = s.samples_per_channel;
  side.gauss_points = config.quality.gauss_points;
  side.shadows = ph.shadows;
  side.beta_eff_rad = s.beta_eff_rad();
  side.vertical_beam = ph.beam_pattern ? s.vertical_beam : VerticalBeamPattern{};
  side.beam_axis_depression_rad = s.tilt_rad;
  side.backscatter = ph.backscatter;
  side.object_glints = ph.object_glints;
  side.materials = scene.materials.all();
  side.spreading = ph.spreading;
  side.absorption_db_per_m = alpha_db_per_m;
  side.calibration_k = ph.calibration_k;
  side.pulse_window_m = s.pulse_window_m() > s.sample_spacing_m() ? s.pulse_window_m() : 0.0;
  side.truth = config.truth || config.noise.model == NoiseConfig::Model::kSpeckle;
  // The speckle keys need only the contributor's position and material: the grazing angle (an
  // asin per sample) only for the output truth.
  side.truth_grazing = config.truth;
  side.validate();
  return side;
}

// The TVG of `config` (output.tvg), absorption alpha_db_per_m.
Tvg tvg_of(const SimulationConfig& config, double alpha_db_per_m) {
  Tvg tvg;
  tvg.law = config.output.tvg;
  tvg.absorption_db_per_m = alpha_db_per_m;
  tvg.spreading_db_per_decade = config.output.tvg_spreading_db_per_decade;
  tvg.absorption_share = config.output.tvg_absorption_share;
  tvg.validate();
  return tvg;
}

// The noise-free echo of a flat seabed of the default material at the reference altitude: its
// mean over the far tenth of the range and its peak (raw), and its mean over the middle tenth
// after the TVG.
struct FlatSeabedEcho {
  double far_raw = 0.0, peak_raw = 0.0, mid = 0.0;
};

FlatSeabedEcho flat_seabed_echo(const Scene& scene, const SideParams& side, const Tvg& tvg,
                                double reference_altitude_m, double max_range_m) {
  BeamProfile flat;
  flat.sensor_z_m = reference_altitude_m;
  flat.add_node(0.0, 0.0, 0, scene.material_map.default_material());
  flat.add_node(max_range_m, 0.0, 0, scene.material_map.default_material());
  SideParams p = side;
  p.truth = false;
  SideEcho echo;
  render_side(flat, p, echo);
  const std::size_t n = side.samples;
  auto mean_over = [&](const std::vector<double>& v, double from, double to) {
    const auto i0 = std::min(n - 1, static_cast<std::size_t>(from * static_cast<double>(n)));
    const auto i1 = std::max(i0 + 1, static_cast<std::size_t>(to * static_cast<double>(n)));
    double sum = 0.0;
    for (std::size_t i = i0; i < std::min(i1, n); ++i) sum += v[i];
    return sum / static_cast<double>(std::min(i1, n) - i0);
  };
  FlatSeabedEcho r;
  r.far_raw = mean_over(echo.intensity, 0.9, 1.0);
  r.peak_raw = *std::max_element(echo.intensity.begin(), echo.intensity.end());
  apply_tvg(tvg, 0.5 * side.sample_spacing_m, side.sample_spacing_m, echo.intensity);
  r.mid = mean_over(echo.intensity, 0.45, 0.55);
  return r;
}

// For the automatic gain: the median of unit-mean speckle of the default material through the
// detector (from the noise code itself); 1 without speckle.
double speckle_median(const SimulationConfig& config, const Scene& scene, const SideParams& side,
                      const SensorModel& looks) {
  if (config.noise.model != NoiseConfig::Model::kSpeckle) return 1.0;
  const std::size_t def = scene.material_map.default_material();
  const double nu = config.noise.texture && def < side.materials.size()
                        ? side.materials[def].texture_shape_nu
                        : 0.0;
  return detected_median_of_unit_mean(looks, nu, config.seed);
}

// A gain that rounds the seabed itself to 0 gives an all-black survey: refused before any ping
// is rendered. mid: the calibration seabed's mid-range power before the gain, mid_out after.
void check_seabed_survives_rounding(const Quantizer& quantizer, bool amplitude, double mid,
                                    double mid_out, double auto_gain_db) {
  const double stored_mid = amplitude ? std::sqrt(mid_out) : mid_out;
  if (quantizer.round_to_integer && mid > 0.0 && stored_mid < 0.5) {
    char msg[400];
    std::snprintf(msg, sizeof msg,
                  "output.gain_db = %.6g puts the mid-range seabed echo at %.3g counts, so every "
                  "sample would round to 0. Violated constraint: gain_db >= %.4g (the automatic "
                  "gain is %.4g dB)",
                  quantizer.gain_db, stored_mid, 10.0 * std::log10((amplitude ? 0.25 : 0.5) / mid),
                  auto_gain_db);
    throw InputError(msg);
  }
}

// The along-track position of a ping (PingPose::along_track_m, else the sensor's position along
// its heading).
double along_track_position_m(const PingPose& pose) {
  const Eigen::Vector2d fwd(std::sin(pose.heading_rad), std::cos(pose.heading_rad));
  return std::isfinite(pose.along_track_m) ? pose.along_track_m : pose.sensor_xy_m.dot(fwd);
}

// The paper's image-domain noise of `nc` (Rayleigh sigma in output units).
PaperNoise paper_noise_of(const NoiseConfig& nc, double rayleigh_sigma, std::uint64_t seed) {
  PaperNoise pn;
  pn.uniform_half_width = nc.paper_uniform_half_width;
  pn.rayleigh_sigma = rayleigh_sigma;
  pn.seed = seed;
  if (!std::isnan(nc.paper_uniform_variance)) {  // the paper's U(0, g'), variance gamma
    pn.uniform_half_width = std::sqrt(3.0 * nc.paper_uniform_variance);
    pn.uniform_from_zero = true;
  }
  return pn;
}

}  // namespace

double Simulator::gain_db() const {
  return cal_->quantizer.gain_db;
}
const SideParams& Simulator::side_params() const {
  return cal_->side;
}

Simulator::Simulator(const Scene& scene, const SimulationConfig& config,
                     double reference_altitude_m, const std::vector<PingPose>& pilot)
    : Simulator(std::make_shared<const Scene>(scene), config, reference_altitude_m, pilot) {}

Simulator::Simulator(std::shared_ptr<const Scene> shared_scene, const SimulationConfig& config,
                     double reference_altitude_m, const std::vector<PingPose>& pilot)
    : scene_(std::move(shared_scene)), config_(config), cal_(std::make_unique<Calibration>()) {
  if (!scene_) throw InputError("simulator: scene = null. Violated constraint: a scene");
  const Scene& scene = *scene_;
  config_.validate();
  if (scene.bathymetry.empty()) throw InputError("simulator: the scene has no bathymetry");
  const SonarConfig& s = config_.sonar;
  const PhysicsConfig& ph = config_.physics;
  alpha_db_per_m_ = ph.absorption ? francois_garrison_db_per_m(s.frequency_hz, ph.water) : 0.0;

  cal_->side = side_params_of(config_, scene, alpha_db_per_m_);
  cal_->tvg = tvg_of(config_, alpha_db_per_m_);

  // Global calibration from a flat seabed of the default material at the reference altitude:
  // the gain (seabed_median_dbfs) and the noise power (SNR at max range).
  const FlatSeabedEcho flat =
      flat_seabed_echo(scene, cal_->side, cal_->tvg, reference_altitude_m, s.max_range_m);
  const double snr = std::pow(10.0, config_.noise.snr_at_max_range_db / 10.0);
  noise_power_ = (flat.far_raw > 0.0 ? flat.far_raw : flat.peak_raw) / snr;
  const double mid = flat.mid;
  cal_->quantizer.max_value = config_.output.max_value;
  cal_->quantizer.round_to_integer = config_.output.round_to_integer;
  cal_->quantizer.gain_db = config_.output.gain_db;
  // The stored value of a power p is sqrt(p) (amplitude) or p (intensity).
  const bool amplitude = config_.output.quantity == SampleQuantity::amplitude;
  SensorModel looks = SensorModel::make(config_, 0.0, reference_altitude_m);
  const double q = speckle_median(config_, scene, cal_->side, looks);
  const double target_power =
      amplitude
          ? std::pow(config_.output.max_value, 2.0) *
                std::pow(10.0, config_.output.seabed_median_dbfs / 10.0)
          : config_.output.max_value * std::pow(10.0, config_.output.seabed_median_dbfs / 10.0);
  const double auto_gain_db = mid > 0.0 ? 10.0 * std::log10(target_power / (mid * q)) : 0.0;
  if (std::isnan(cal_->quantizer.gain_db)) cal_->quantizer.gain_db = auto_gain_db;
  cal_->quantizer.validate();
  // Paper noise (image domain): the mean of its Rayleigh term, sigma sqrt(pi/2), lies SNR dB
  // below the calibrated mid-range seabed level.
  const double mid_out = mid * std::pow(10.0, cal_->quantizer.gain_db / 10.0);
  paper_sigma_out_ = mid_out / (snr * std::sqrt(kPi / 2.0));
  cal_->sensor = SensorModel::make(config_, mid_out, reference_altitude_m);
  // K = 1/Imax per ping: the image is in units of each ping's maximum (full scale), the gain
  // cancels, and the Rayleigh mean lies SNR dB below full scale.
  const bool per_ping = config_.output.normalise == OutputScaling::Normalise::per_ping_max;
  if (per_ping) paper_sigma_out_ = cal_->sensor.full_scale_power / (snr * std::sqrt(kPi / 2.0));
  if (!per_ping)
    check_seabed_survives_rounding(cal_->quantizer, amplitude, mid, mid_out, auto_gain_db);

  if (config_.quality.along_track_planes == QualityConfig::kAutoPlanes) {
    along_track_ = choose_along_track_planes(
        pilot.empty() ? pilot_poses(scene.bathymetry, reference_altitude_m, s.max_range_m) : pilot);
  } else {
    along_track_.planes = config_.quality.along_track_planes;
    along_track_.object_planes = along_track_.planes;
  }
  cal_->planes = make_along_track_planes(s, along_track_.planes, cal_->side.beta_eff_rad);
  if (along_track_.object_planes > along_track_.planes) {
    cal_->object_planes =
        make_along_track_planes(s, along_track_.object_planes, cal_->side.beta_eff_rad);
    cal_->object_finder = std::make_unique<ObjectPlaneRefiner>(
        scene.objects, s, cal_->object_planes, cal_->side.beta_eff_rad);
  }
  if (config_.quality.small_object_planes && !scene.objects.empty()) {
    cal_->refiner = std::make_unique<ObjectPlaneRefiner>(scene.objects, s, cal_->planes,
                                                         cal_->side.beta_eff_rad);
  }
}

Simulator::~Simulator() = default;

void Simulator::WorkspaceDeleter::operator()(Workspace* ws) const {
  delete ws;
}

Simulator::WorkspacePtr Simulator::make_workspace() const {
  WorkspacePtr ws(new Workspace());
  ws->params = cal_->side;
  // TVG and quantiser gain per sample, once: the noise stage then costs one multiply.
  ws->tvg_gain.assign(cal_->side.samples, 1.0);
  apply_tvg(cal_->tvg, 0.5 * cal_->side.sample_spacing_m, cal_->side.sample_spacing_m,
            ws->tvg_gain);
  const double g = std::pow(10.0, cal_->quantizer.gain_db / 10.0);
  for (double& v : ws->tvg_gain) v *= g;
  ws->sensor_mean = SensorMeanTables(cal_->sensor, cal_->side, ws->tvg_gain);
  ws->sample_hash.resize(cal_->side.samples);
  for (std::size_t i = 0; i < cal_->side.samples; ++i) ws->sample_hash[i] = splitmix64(i);
  return ws;
}

void Simulator::quantise(const Workspace& ws, bool scaled, float* out, std::uint32_t& saturated,
                         std::uint32_t& invalid) const {
  const std::size_t n = cal_->side.samples;
  const double maxv = cal_->quantizer.max_value;
  const bool round = cal_->quantizer.round_to_integer;
  const bool amplitude = cal_->sensor.amplitude;
  saturated = 0;
  invalid = 0;
  // The transmit ring-down saturates the first samples (not counted as saturation: it is no
  // echo the gain could keep in range).
  const double ring = cal_->sensor.ring_down_m / cal_->side.sample_spacing_m - 0.5;
  const std::size_t ring_samples =
      ring > 0.0 ? std::min(n, static_cast<std::size_t>(std::ceil(ring))) : 0;
  std::fill(out, out + ring_samples, static_cast<float>(maxv));
  sensor_kernel::QuantiseArgs q;
  q.power = ws.accum.data();
  q.gain = scaled ? nullptr : ws.tvg_gain.data();
  q.first = ring_samples;
  q.n = n;
  q.amplitude = amplitude;
  q.round = round;
  q.max_value = maxv;
  sensor_kernel::quantise(q, out, saturated, invalid);
}

double Simulator::per_ping_max_scale(const PingPose& pose, Workspace& ws) const {
  double imax = 0.0;
  for (const bool starboard : {false, true}) {
    render_planes(pose, starboard, cal_->planes, true, false, ws, nullptr);
    for (std::size_t i = 0; i < cal_->side.samples; ++i) {
      imax = std::max(imax, ws.accum[i] * ws.tvg_gain[i]);
    }
  }
  return imax > 0.0 && std::isfinite(imax) ? cal_->sensor.full_scale_power / imax : 1.0;
}

void Simulator::render_side_output(const PingPose& pose, std::uint64_t noise_key, bool starboard,
                                   Workspace& ws, const SideSpans& out, RenderTimings* timings,
                                   double scale) const {
  const std::size_t n = cal_->side.samples;
  const auto now = [timings] { return timings != nullptr ? Clock::now() : Clock::time_point{}; };
  const SideGeometry geo =
      render_planes(pose, starboard, cal_->planes, true, cal_->side.truth, ws, timings);
  if (scale != 1.0) {
    for (std::size_t i = 0; i < n; ++i) ws.accum[i] *= scale;  // K = 1/Imax (output.normalise)
  }
  const auto t2 = now();
  const NoiseConfig& nc = config_.noise;
  const std::uint64_t ping = noise_key;
  PatchKey patch;
  patch.line_side = hash_combine(static_cast<std::uint64_t>(pose.line), starboard ? 1 : 0);
  patch.along_track_m = along_track_position_m(pose);
  add_sensor_mean_terms(cal_->sensor, cal_->side, ws.sensor_mean, pose.altitude_m,
                        ws.params.beam_axis_depression_rad, ws.accum, &patch);
  if (config_.clean_samples) {
    std::uint32_t unused_saturated = 0, unused_invalid = 0;
    quantise(ws, false, out.clean_samples, unused_saturated, unused_invalid);
  }
  bool scaled = false;  // accum already in output units (TVG and gain applied)
  if (nc.model == NoiseConfig::Model::kPaper) {
    // The paper's eq. (2) is an image-domain model: applied to the TVG'd, calibrated intensity,
    // so that its additive Rayleigh term is not amplified by the TVG at far range.
    for (std::size_t i = 0; i < n; ++i) ws.accum[i] *= ws.tvg_gain[i];
    scaled = true;
    ping_sample_keys(ping, starboard, ws.sample_hash, ws.noise_keys);
    apply_paper_noise(paper_noise_of(nc, paper_sigma_out_, config_.seed), ws.noise_keys, ws.accum);
  } else if (nc.model == NoiseConfig::Model::kSpeckle) {
    ping_sample_keys(ping, starboard, ws.sample_hash, ws.noise_keys);
    add_speckle(pose, starboard, geo, ws, scale);
    scaled = true;
  }

  // TVG and quantisation (precomputed per-sample gain).
  quantise(ws, scaled, out.samples, *out.saturated, *out.invalid);

  if (config_.truth) copy_truth(ws, geo, out);
  if (timings) timings->noise_s += seconds_since(t2);
}

void Simulator::add_speckle(const PingPose& pose, bool starboard, const SideGeometry& geo,
                            Workspace& ws, double scale) const {
  const std::size_t n = cal_->side.samples;
  const SideEcho& e = ws.echo;
  const NoiseConfig& nc = config_.noise;
  const Eigen::Vector2d& nadir = geo.nadir_xy_m;
  const Eigen::Vector2d& central_dir = geo.central_dir;
  // Frozen speckle: the key of a sample is the seabed cell of its dominant contributor.
  // Neighbouring samples often fall in the same cell: its key is then reused (same value).
  const double cell = nc.freeze_cell_m > 0 ? nc.freeze_cell_m : config_.sonar.range_resolution_m();
  ws.keys.resize(n);
  sample_keys::CellFrame frame;
  frame.nx = nadir.x();
  frame.ny = nadir.y();
  frame.dx = central_dir.x();
  frame.dy = central_dir.y();
  frame.inv_cell = 1.0 / cell;  // one division per side instead of three per sample
  sample_keys::ground_cell_keys(frame, e.truth_class.data(), e.truth_ground_y_m.data(),
                                e.truth_ground_z_m.data(), ws.noise_keys.data(), n, ws.keys.data());
  ws.nu.resize(nc.texture ? n : 0);  // every entry written below (no memset per side)
  if (nc.texture) {
    const std::vector<Material>& materials = cal_->side.materials;
    for (std::size_t i = 0; i < n; ++i) {
      const SampleClass cls = e.truth_class[i];
      ws.nu[i] = cls == SampleClass::seabed || cls == SampleClass::object
                     ? materials[e.truth_material[i]].texture_shape_nu
                     : 0.0;
    }
  }
  SpeckleNoise sn;
  sn.thermal_noise_power = noise_power_ * scale;
  sn.seed = config_.seed;
  AlongTrackField field;
  if (nc.along_track_correlation) {
    field.along_track_m = along_track_position_m(pose);
    field.key = hash_combine(static_cast<std::uint64_t>(pose.line), starboard ? 1 : 0);
    field.sample_spacing_m = cal_->side.sample_spacing_m;
    field.beam_3db_rad = config_.sonar.horizontal_beam_width_rad;
    field.seed = config_.seed;
    field.first_sample =
        std::isfinite(pose.altitude_m) && pose.altitude_m > 0.0
            ? static_cast<std::size_t>(pose.altitude_m / cal_->side.sample_spacing_m)
            : 0;
    field.ping_spacing_m = pose.speed_m_s * config_.sonar.effective_ping_period_s();
    if (nc.aperture_translation) field.array_length_m = config_.sonar.array_length_m();
  }
  detect_speckle(cal_->sensor, sn, ws.keys, ws.noise_keys, ws.nu, ws.tvg_gain,
                 nc.along_track_correlation ? &field : nullptr, ws.detector, ws.accum);
}

void Simulator::copy_truth(const Workspace& ws, const SideGeometry& geo,
                           const SideSpans& out) const {
  const std::size_t n = cal_->side.samples;
  const SideEcho& e = ws.echo;
  const Eigen::Vector2d& nadir = geo.nadir_xy_m;
  const Eigen::Vector2d& central_dir = geo.central_dir;
  std::copy(e.truth_class.begin(), e.truth_class.begin() + static_cast<std::ptrdiff_t>(n),
            out.truth_class);
  std::copy(e.truth_label.begin(), e.truth_label.begin() + static_cast<std::ptrdiff_t>(n),
            out.truth_label);
  for (std::size_t i = 0; i < n; ++i) {
    out.truth_grazing_rad[i] = static_cast<float>(e.truth_grazing_rad[i]);
  }
  // A sample's ground position is the nadir + a float ground range along the side's
  // across-track direction, computed only where asked for (docs/architecture.md "Per-sample
  // truth").
  if (out.truth_ground_range_m) {
    for (std::size_t i = 0; i < n; ++i) {
      out.truth_ground_range_m[i] = static_cast<float>(e.truth_ground_y_m[i]);  // NaN stays NaN
    }
    *out.truth_nadir_xy_m = nadir;
    *out.truth_across_dir = central_dir;
  }
  if (out.truth_ground_x_m) {
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector2d p = SideOutput::ground_position(
          nadir, central_dir, static_cast<float>(e.truth_ground_y_m[i]));
      out.truth_ground_x_m[i] = p.x();
      out.truth_ground_y_m[i] = p.y();
    }
  }
}

void Simulator::render_ping(const PingPose& pose, Workspace& ws, RenderedPing& out,
                            RenderTimings* timings) const {
  out.pose = pose;
  if (!out.pose.ping_index) {
    constexpr std::uint64_t kAutomaticKeyBase = std::uint64_t{1} << 63;
    out.pose.ping_index = kAutomaticKeyBase | automatic_keys_.fetch_add(1);
  }
  const std::uint64_t key = *out.pose.ping_index;
  render_sides(pose, key, ws, spans_of(out.port), spans_of(out.starboard), timings);
}

std::size_t Simulator::side_samples() const {
  return cal_->side.samples;
}

Simulator::SideSpans Simulator::spans_of(SideOutput& s) const {
  const std::size_t n = cal_->side.samples;
  SideSpans o;
  s.samples.resize(n);
  o.samples = s.samples.data();
  if (config_.clean_samples) {
    s.clean_samples.resize(n);
    o.clean_samples = s.clean_samples.data();
  } else {
    s.clean_samples.clear();
  }
  if (config_.truth) {
    s.truth_class.resize(n);
    s.truth_label.resize(n);
    s.truth_grazing_rad.resize(n);
    s.truth_ground_range_m.resize(n);
    o.truth_class = s.truth_class.data();
    o.truth_label = s.truth_label.data();
    o.truth_grazing_rad = s.truth_grazing_rad.data();
    o.truth_ground_range_m = s.truth_ground_range_m.data();
    o.truth_nadir_xy_m = &s.truth_nadir_xy_m;
    o.truth_across_dir = &s.truth_across_dir;
  }
  o.saturated = &s.saturated;
  o.invalid = &s.invalid;
  return o;
}

void Simulator::render_sides(const PingPose& pose, std::uint64_t key, Workspace& ws,
                             const SideSpans& port, const SideSpans& starboard,
                             RenderTimings* timings) const {
  const double scale = config_.output.normalise == OutputScaling::Normalise::per_ping_max
                           ? per_ping_max_scale(pose, ws)
                           : 1.0;
  render_side_output(pose, key, false, ws, port, timings, scale);
  render_side_output(pose, key, true, ws, starboard, timings, scale);
}

}  // namespace sonarsynth
