// SPDX-License-Identifier: MIT
#include "sonarsynth/sensor_effects.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "sonarsynth/along_track_lattice.hpp"
#include "sonarsynth/backscatter.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/noise.hpp"
#include "sonarsynth/render_math.hpp"
#include "sonarsynth/sensor_kernel.hpp"
#include "sonarsynth/sensor_mean_simd.hpp"

namespace sonarsynth {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kHalfPi = 1.57079632679489661923;

bool on(double level) {
  return std::isfinite(level);
}
double db_to_power(double db) {
  return std::pow(10.0, db / 10.0);
}

// 4-point Gauss–Legendre on [0, 1] (Abramowitz & Stegun, Table 25.4).
constexpr double kGx[4] = {
    0.5 * (1.0 - 0.86113631159405257522), 0.5 * (1.0 - 0.33998104358485626480),
    0.5 * (1.0 + 0.33998104358485626480), 0.5 * (1.0 + 0.86113631159405257522)};
constexpr double kGw[4] = {0.5 * 0.34785484513745385737, 0.5 * 0.65214515486254614263,
                           0.5 * 0.65214515486254614263, 0.5 * 0.34785484513745385737};
// 2-point Gauss–Legendre on [0, 1].
constexpr double kG2x[2] = {0.5 * (1.0 - 0.57735026918962576451),
                            0.5 * (1.0 + 0.57735026918962576451)};
constexpr double kG2w[2] = {0.5, 0.5};

// Across-track distance y (at depth h below the sensor) where the two-way main lobe, followed
// from the axis towards nadir, first falls to `floor`; NaN if it does not before nadir.
double side_lobe_crossing_y(const VerticalBeamPattern& beam, double floor, double h,
                            double axis_depression_rad) {
  const double nadir_off = kHalfPi - axis_depression_rad;
  if (!(nadir_off > 0.0) || !(beam.two_way(nadir_off) < floor)) return kNaN;
  // First off-axis angle below the floor on a 0.5 deg scan, then bisection.
  double lo = 0.0, hi = nadir_off;
  for (double off = 0.0; off < nadir_off; off += 0.0087266) {
    if (beam.two_way(off) < floor) {
      hi = off;
      break;
    }
    lo = off;
  }
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    (beam.two_way(mid) < floor ? hi : lo) = mid;
  }
  return h / std::tan(axis_depression_rad + 0.5 * (lo + hi));
}

}  // namespace

void SensorConfig::validate() const {
  auto bad = [](const std::string& what) { throw InputError("sensor: " + what); };
  auto num = [](double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  };
  if (on(first_return_reflection_db) && !(first_return_reflection_db <= 0.0)) {
    bad("first_return_reflection_db = " + num(first_return_reflection_db) +
        ". Violated constraint: <= 0 (a reflection coefficient is at most 1)");
  }
  if (!(first_return_rms_slope > 0.0 && first_return_rms_slope <= 1.0)) {
    bad("first_return_rms_slope = " + num(first_return_rms_slope) +
        ". Violated constraint: 0 < first_return_rms_slope <= 1");
  }
  if (!(side_lobe_db <= 0.0)) {
    bad("side_lobe_db = " + num(side_lobe_db) + ". Violated constraint: side_lobe_db <= 0");
  }
  for (const auto& [name, v] :
       {std::pair{"volume_texture_shape", volume_texture_shape},
        std::pair{"shadow_fill_texture_shape", shadow_fill_texture_shape}}) {
    if (on(v) && !(v >= 0.01 && v <= 1000.0)) {
      bad(std::string(name) + " = " + num(v) + ". Violated constraint: 0.01 <= shape <= 1000");
    }
  }
  for (const auto& [name, v] :
       {std::pair{"volume_patch_along_track_m", volume_patch_along_track_m},
        std::pair{"shadow_fill_patch_along_track_m", shadow_fill_patch_along_track_m},
        std::pair{"shadow_fill_patch_range_m", shadow_fill_patch_range_m}}) {
    if (!(v >= 1e-3 && v <= 1e6)) {
      bad(std::string(name) + " = " + num(v) + ". Violated constraint: 0.001 <= " + name +
          " <= 1e6");
    }
  }
  if (!(volume_patch_range_m == 0.0 ||
        (volume_patch_range_m >= 1e-3 && volume_patch_range_m <= 1e6))) {
    bad("volume_patch_range_m = " + num(volume_patch_range_m) +
        ". Violated constraint: 0 (the range resolution) or 0.001 <= volume_patch_range_m <= 1e6");
  }
  if (on(ring_down_m) && !(ring_down_m >= 0.0)) {
    bad("ring_down_m = " + num(ring_down_m) + ". Violated constraint: ring_down_m >= 0");
  }
  for (const auto& [name, v] : {std::pair{"volume_reverberation_db", volume_reverberation_db},
                                std::pair{"shadow_fill_db", shadow_fill_db}}) {
    if (on(v) && !(v <= 0.0)) {
      bad(std::string(name) + " = " + num(v) +
          ". Violated constraint: <= 0 (not above the seabed it is relative to)");
    }
  }
  for (const auto& [name, v] : {std::pair{"noise_floor_dbfs", noise_floor_dbfs},
                                std::pair{"volume_reverberation_db", volume_reverberation_db},
                                std::pair{"shadow_fill_db", shadow_fill_db}}) {
    if (std::isinf(v)) bad(std::string(name) + " is infinite. Violated constraint: finite or off");
  }
}

SensorConfig SensorConfig::none() {
  constexpr double kOff = std::numeric_limits<double>::quiet_NaN();
  SensorConfig c;
  c.noise_floor_dbfs = kOff;
  c.volume_reverberation_db = kOff;
  c.shadow_fill_db = kOff;
  c.first_return_reflection_db = kOff;
  c.ring_down_m = kOff;
  c.volume_texture_shape = kOff;
  c.shadow_fill_texture_shape = kOff;
  return c;
}

std::vector<double> range_filter_taps(const SonarConfig& sonar) {
  const double dr = sonar.sample_spacing_m();
  const double w = sonar.pulse_window_m();
  if (!(w > 0.0) || !(dr > 0.0) || !std::isfinite(w / dr)) return {};
  const bool chirp = sonar.pulse == SonarConfig::Pulse::kChirp;
  // Complex impulse response h(x), x in metres of range: the pulse through its matched filter.
  const auto h = [&](double x) {
    const double u = std::abs(x) / w;
    if (!chirp) return u < 1.0 ? 1.0 - u : 0.0;
    if (u < 1e-12) return 1.0;
    const double a = 3.14159265358979323846 * u;
    return u < 3.0 ? std::sin(a) / a : 0.0;
  };
  const double support_m = chirp ? 3.0 * w : w;
  // Taps k = -K .. K: h integrated over [k - 1/2, k + 1/2] dr (16-point midpoint rule).
  const auto half = static_cast<std::size_t>(std::min(64.0, std::ceil(support_m / dr - 0.5)));
  std::vector<double> taps(2 * half + 1, 0.0);
  double power = 0.0;
  for (std::size_t t = 0; t < taps.size(); ++t) {
    const double k = static_cast<double>(t) - static_cast<double>(half);
    double sum = 0.0;
    for (int q = 0; q < 16; ++q) sum += h((k - 0.5 + (q + 0.5) / 16.0) * dr);
    taps[t] = sum / 16.0;
    power += taps[t] * taps[t];
  }
  if (!(power > 0.0)) return {};
  for (double& v : taps) v /= std::sqrt(power);
  // A single tap (the pulse shorter than a sample spacing): no correlation to model.
  if (taps.size() == 1 || taps[half] > 1.0 - 1e-6) return {};
  return taps;
}

SensorModel SensorModel::make(const SimulationConfig& config, double seabed_power,
                              double reference_altitude_m) {
  const SensorConfig& c = config.sensor;
  const OutputScaling& o = config.output;
  SensorModel m;
  m.amplitude = o.quantity == SampleQuantity::amplitude;
  m.sub_samples = config.noise.model == NoiseConfig::Model::kSpeckle ? o.detector_sub_samples : 1;
  m.detector = o.detector;
  m.full_scale_power = m.amplitude ? o.max_value * o.max_value : o.max_value;
  if (on(c.noise_floor_dbfs) && config.noise.model == NoiseConfig::Model::kSpeckle) {
    // RMS level of the stored quantity: amplitude^2 = power; intensity: the power itself.
    m.floor_power = m.amplitude ? o.max_value * o.max_value * db_to_power(c.noise_floor_dbfs)
                                : o.max_value * db_to_power(c.noise_floor_dbfs);
  }
  if (on(c.volume_reverberation_db))
    m.volume_power = seabed_power * db_to_power(c.volume_reverberation_db);
  m.reference_altitude_m = reference_altitude_m > 0.0 ? reference_altitude_m : 1.0;
  if (on(c.shadow_fill_db)) m.fill_power = seabed_power * db_to_power(c.shadow_fill_db);
  if (on(c.first_return_reflection_db)) {
    m.first_return_rho = db_to_power(c.first_return_reflection_db);
    m.first_return_rms_slope = c.first_return_rms_slope;
    m.side_lobe_two_way = db_to_power(2.0 * c.side_lobe_db);
  }
  // At most a tenth of the range: a ring-down marks the record's start, it does not fill it.
  if (on(c.ring_down_m)) m.ring_down_m = std::min(c.ring_down_m, 0.1 * config.sonar.max_range_m);
  if (o.tvg == TvgLaw::spherical) {
    const double alpha =
        config.physics.absorption
            ? francois_garrison_db_per_m(config.sonar.frequency_hz, config.physics.water)
            : 0.0;
    m.tvg_deficit_exponent = (30.0 - o.tvg_spreading_db_per_decade) / 10.0;
    m.tvg_deficit_per_m = 2.0 * (1.0 - o.tvg_absorption_share) * alpha * std::log(10.0) / 10.0;
  }
  m.mid_range_m = 0.5 * config.sonar.max_range_m;
  m.volume_texture_nu = on(c.volume_texture_shape) ? c.volume_texture_shape : 0.0;
  m.fill_texture_nu = on(c.shadow_fill_texture_shape) ? c.shadow_fill_texture_shape : 0.0;
  m.volume_patch_along_m = c.volume_patch_along_track_m;
  m.volume_patch_range_m =
      c.volume_patch_range_m > 0.0 ? c.volume_patch_range_m : config.sonar.range_resolution_m();
  m.fill_patch_along_m = c.shadow_fill_patch_along_track_m;
  m.fill_patch_range_m = c.shadow_fill_patch_range_m;
  m.patch_seed = config.seed;
  if (config.noise.range_correlation && config.noise.model == NoiseConfig::Model::kSpeckle) {
    m.range_taps = range_filter_taps(config.sonar);
  }
  return m;
}

SensorMeanTables::SensorMeanTables(const SensorModel& m, const SideParams& side,
                                   std::span<const double> out_gain) {
  const std::size_t n = out_gain.size();
  const double dr = side.sample_spacing_m;
  // Volume reverberation falls as r^-2 before the TVG: after 30 log R + 2 alpha R it grows as
  // r, after 20 log R + 2 alpha R it is flat; in general r times what the TVG leaves of the
  // seabed's fall (SensorModel::tvg_deficit), referred to the reference altitude.
  if (m.volume_power > 0.0) {
    const double h = m.reference_altitude_m;
    const double per_m = m.volume_power / (h * m.tvg_deficit(h));
    volume.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double r = (static_cast<double>(i) + 0.5) * dr;
      volume[i] = per_m * r * m.tvg_deficit(r) / out_gain[i];
    }
  }
  // The shadow fill follows the seabed it comes from: flat after the compensating TVG.
  if (m.fill_power > 0.0) {
    fill.resize(n);
    const double ref = m.tvg_deficit(m.mid_range_m);
    for (std::size_t i = 0; i < n; ++i) {
      const double r = (static_cast<double>(i) + 0.5) * dr;
      fill[i] = m.fill_power * m.tvg_deficit(r) / ref / out_gain[i];
    }
  }
  // The patch textures' range geometry (sample i at ur = (i + 1/2) dr / patch: node floor(ur),
  // weight ur - floor(ur)), where there are at most about as many patches as samples.
  const auto cells_of = [&](double range_m, TextureCells& t) {
    const double inv_patch = dr / range_m;
    const double count = static_cast<double>(n);
    if (n == 0 || !(inv_patch * count < 1e15) ||
        !(std::floor((count - 0.5) * inv_patch) + 2.0 <= count + 2.0)) {
      return;
    }
    t.cell.resize(n);
    t.weight.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double ur = (static_cast<double>(i) + 0.5) * inv_patch;
      const double fr = std::floor(ur);
      t.cell[i] = static_cast<std::int64_t>(fr);
      t.weight[i] = ur - fr;
    }
  };
  if (m.volume_power > 0.0 && m.volume_texture_nu > 0.0) {
    cells_of(m.volume_patch_range_m, volume_cells);
  }
  if (m.fill_power > 0.0 && m.fill_texture_nu > 0.0) cells_of(m.fill_patch_range_m, fill_cells);
  texture_nodes.reserve(n + 2);
}

namespace {

// The node values of texture `stream`'s along-track row `along` (row word `row`, unit-mean
// Gamma table t) over the range patches [c0, c1): the tables' row if they keep it, else the
// least recently used row, recomputed. A row holds one contiguous range of computed nodes and
// computes only those it lacks. Rows a ping side reads are at most 2 per texture: 8 rows serve
// both textures of both sides. `capacity` (>= c1) is reserved for every row at the first call.
const double* texture_row(SensorMeanTables& tables, std::uint64_t stream, std::uint64_t along,
                          std::uint64_t row, const UnitGammaTable& t, std::size_t c0,
                          std::size_t c1, std::size_t capacity) {
  constexpr std::size_t kRows = 8;
  if (tables.texture_rows.size() != kRows) {
    tables.texture_rows.resize(kRows);
    for (auto& r : tables.texture_rows) r.nodes.reserve(capacity);  // no allocation per ping
  }
  ++tables.texture_clock;
  SensorMeanTables::TextureRow* pick = &tables.texture_rows[0];
  for (auto& r : tables.texture_rows) {
    if (r.used && r.stream == stream && r.along == along) {
      pick = &r;
      break;
    }
    if (!r.used || (pick->used && r.last_use < pick->last_use)) pick = &r;
  }
  SensorMeanTables::TextureRow& r = *pick;
  if (!(r.used && r.stream == stream && r.along == along)) {
    r.used = true;
    r.stream = stream;
    r.along = along;
    r.lo = r.hi = c0;
  }
  r.last_use = tables.texture_clock;
  if (r.nodes.size() < c1) r.nodes.resize(c1);
  const auto compute = [&](std::size_t from, std::size_t to) {
    for (std::size_t c = from; c < to; ++c) {
      r.nodes[c] = t(high32_midpoint(splitmix_stream(row, c) << 32));
    }
  };
  // Extend [lo, hi) to cover [c0, c1) (and any gap between them).
  if (c0 < r.lo) compute(c0, r.lo);
  if (c1 > r.hi) compute(r.hi, c1);
  r.lo = std::min(r.lo, c0);
  r.hi = std::max(r.hi, c1);
  return r.nodes.data();
}

// The first bottom return of `altitude_m` into r (its cache entry): per bin from the first return
// on, the per-bin integral in across-track distance (NaN where nothing is added).
void first_return_bins(const SensorModel& m, const SideParams& side, double altitude_m,
                       double axis_depression_rad, std::size_t n,
                       SensorMeanTables::FirstReturn& out) {
  const double dr = side.sample_spacing_m;
  out.altitude_m = altitude_m;
  out.axis_depression_rad = axis_depression_rad;
  out.samples = n;
  out.first = static_cast<std::size_t>(std::floor(altitude_m / dr));
  out.values.clear();
  out.values.reserve(n);  // once: no allocation per altitude
  const double h = altitude_m, h2 = h * h;
  const double kappa = 2.0 * side.absorption_db_per_m * std::log(10.0) / 10.0;
  // sigma = lobe.peak sec^4 exp(-lobe.exponent(tan^2)) (backscatter.hpp).
  const KirchhoffLobe lobe = KirchhoffLobe::make(m.first_return_rho, m.first_return_rms_slope);
  const double coef = side.calibration_k * side.beta_eff_rad * lobe.peak;
  // sigma < e^-20 (2e-9) of its peak beyond tan^2 theta = 40 s^2, orders of magnitude below
  // the diffuse seabed of the same bins: stop there.
  constexpr double kFirstReturnCutExponent = 20.0;
  const double tan2_max = kFirstReturnCutExponent / lobe.inv_2s2;
  const double y_kink =
      side_lobe_crossing_y(side.vertical_beam, m.side_lobe_two_way, h, axis_depression_rad);
  // One exp() per point: sigma's exp(-tan^2 / 2 s^2), the absorption and, for a Gaussian beam
  // (two-way b^2 = exp(-gc off^2), docs/physics.md §1.3), max(b^2, floor) as
  // exp(max(-gc off^2, ln floor)) share one exponent.
  const bool gaussian = side.vertical_beam.shape == VerticalBeamShape::gaussian;
  const double w3 = side.vertical_beam.width_3db_rad;
  const double gc = gaussian ? 8.0 * std::log(2.0) / (w3 * w3) : 0.0;
  const double ln_floor = std::log(m.side_lobe_two_way);  // -inf without a floor
  const double inv_h2 = 1.0 / h2;
  const double slope_h = m.first_return_rms_slope * h;
  for (std::size_t i = out.first; i < n; ++i) {
    const double r0 = static_cast<double>(i) * dr, r1 = r0 + dr;
    const double y0 = r0 > h ? std::sqrt(r0 * r0 - h2) : 0.0;
    if (y0 * y0 > tan2_max * h2) break;
    const double y1 = std::sqrt(std::max(0.0, r1 * r1 - h2));
    const double dy = y1 - y0;
    if (!(dy > 0.0)) {
      out.values.push_back(kNaN);
      continue;
    }
    // Depression atan2(h, y) = theta_c + atan(x), x = h (yc - y) / (yc y + h^2) the angle from
    // the bin's middle yc (both rays in the first quadrant): one atan2 per bin, the truncated
    // atan series of render_math per point where |x| < 0.1 on the whole bin (x is monotone
    // in y, so its ends bound it), atan2 otherwise.
    const double yc = 0.5 * (y0 + y1);
    const double theta_c = std::atan2(h, yc);
    const double x_end = std::max(std::abs(h * (yc - y0) / (yc * y0 + h2)),
                                  std::abs(h * (yc - y1) / (yc * y1 + h2)));
    const int terms = x_end < 0.1 ? render_math::atan_terms(x_end) : 0;
    // The beam term max(b^2, side lobe) has a kink where the main lobe meets the floor: a
    // split point of the rule.
    double sum = 0.0;
    const double cut = y_kink > y0 && y_kink < y1 ? y_kink : y1;
    // Bins narrow against their distance from nadir and the lobe's width s h (far from the
    // sensor): the integrand is smooth on them, and 2-point Gauss–Legendre (error ~ (dy /
    // scale)^4 / 4320 relative, below 1e-9 here) does what 4 points do at half the cost.
    const bool smooth = cut == y1 && dy < 0.02 * y0 && dy < 0.02 * slope_h;
    const double* gx = smooth ? kG2x : kGx;
    const double* gw = smooth ? kG2w : kGw;
    const int points = smooth ? 2 : 4;
    for (const auto& [a, b] : {std::pair{y0, cut}, std::pair{cut, y1}}) {
      const double w = b - a;
      if (!(w > 0.0)) continue;
      for (int g = 0; g < points; ++g) {
        const double y = a + gx[g] * w;
        const double y2 = y * y;
        const double r2 = y2 + h2, r = std::sqrt(r2);
        const double sec2 = r2 * inv_h2;  // 1 / cos^2
        double theta;
        if (terms > 0) {
          const double x = h * (yc - y) / (yc * y + h2);
          theta = theta_c + x * render_math::atan_poly(x * x, terms);
        } else {
          theta = std::atan2(h, y);
        }
        const double off = theta - axis_depression_rad;
        double expo = -lobe.exponent(y2 * inv_h2) - kappa * r;
        double v = sec2 * sec2 * (side.spreading ? 1.0 / (r2 * r) : r);
        if (gaussian) {
          expo += std::max(-gc * off * off, ln_floor);
        } else {
          v *= std::max(side.vertical_beam.two_way(off), m.side_lobe_two_way);
        }
        sum += gw[g] * w * v * render_math::exp_table(expo);
      }
    }
    out.values.push_back(coef * sum);
  }
}

}  // namespace

void add_sensor_mean_terms(const SensorModel& m, const SideParams& side, double altitude_m,
                           double axis_depression_rad, std::span<const double> out_gain,
                           std::span<double> mean) {
  SensorMeanTables tables(m, side, out_gain);
  add_sensor_mean_terms(m, side, tables, altitude_m, axis_depression_rad, mean);
}

void add_sensor_mean_terms(const SensorModel& m, const SideParams& side, SensorMeanTables& tables,
                           double altitude_m, double axis_depression_rad, std::span<double> mean,
                           const PatchKey* patch) {
  const std::size_t n = mean.size();
  const double dr = side.sample_spacing_m;
  const bool have_altitude = std::isfinite(altitude_m) && altitude_m > 0.0;
  const std::size_t nv = std::min(n, tables.volume.size());
  const auto first = have_altitude ? static_cast<std::size_t>(std::floor(altitude_m / dr)) : n;
  const std::size_t nf = std::min(n, tables.fill.size());
  const bool patchy = patch != nullptr && std::isfinite(patch->along_track_m) &&
                      (m.volume_texture_nu > 0.0 || m.fill_texture_nu > 0.0);
  if (!patchy) {
    for (std::size_t i = 0; i < nv; ++i) mean[i] += tables.volume[i];
    for (std::size_t i = first; i < nf; ++i) mean[i] += tables.fill[i];
  } else {
    // Unit-mean Gamma textures per patch (keyed by line and side, along-track and range
    // patch): volume scatterers (fish, bubbles) are sparse and the multipath reaching shadows
    // blotchy. The texture is interpolated bilinearly between patch nodes, so that it fades
    // over consecutive pings and samples instead of switching at patch edges.
    const std::uint64_t base =
        hash_combine(splitmix64(m.patch_seed ^ 0x9a7c4e5fULL), patch->line_side);
    const auto add_textured = [&](const std::vector<double>& level, std::size_t from,
                                  std::size_t to, double nu, double along_m, double range_m,
                                  std::uint64_t salt, const SensorMeanTables::TextureCells& g) {
      if (!(nu > 0.0)) {
        for (std::size_t i = from; i < to; ++i) mean[i] += level[i];
        return;
      }
      const double ua = patch->along_track_m / along_m;
      const double inv_patch = dr / range_m;
      // Patch indices must fit an integer (validate() keeps patches >= 1 mm; a survey far beyond
      // 1e12 m of line is not textured).
      if (!(std::abs(ua) < 1e15) || !(inv_patch * static_cast<double>(to) < 1e15)) {
        for (std::size_t i = from; i < to; ++i) mean[i] += level[i];
        return;
      }
      const UnitGammaTable& t = UnitGammaTable::get(nu);
      const double fa = std::floor(ua);
      const double wa = ua - fa;
      const auto a0 = static_cast<std::uint64_t>(static_cast<std::int64_t>(fa));
      const std::uint64_t stream = base ^ salt;
      const std::uint64_t row0 = splitmix_stream(stream, a0);
      const std::uint64_t row1 = splitmix_stream(stream, a0 + 1);
      const auto value = [&](std::uint64_t row, std::uint64_t c) {
        return t(high32_midpoint(splitmix_stream(row, c) << 32));
      };
      if (to > from && g.cell.size() >= to) {
        // The node values of rows a0 and a0 + 1, kept in the tables between pings (a patch spans
        // several pings), blended at the ping's along-track position for the range patches of
        // [from, to); then one vector pass over the samples.
        const auto c0 = static_cast<std::size_t>(g.cell[from]);
        const auto c1 = static_cast<std::size_t>(g.cell[to - 1]) + 2;
        const double* n0 = texture_row(tables, stream, a0, row0, t, c0, c1, n + 2);
        const double* n1 = texture_row(tables, stream, a0 + 1, row1, t, c0, c1, n + 2);
        tables.texture_nodes.resize(std::max(tables.texture_nodes.size(), c1));
        double* nodes = tables.texture_nodes.data();
        sensor_mean::blend_rows(n0, n1, wa, c0, c1, nodes);
        sensor_mean::add_textured(level.data(), g.cell.data(), g.weight.data(), nodes, from, to,
                                  mean.data());
        return;
      }
      // Patches finer than the samples: the nodes each sample needs, as it needs them.
      // Patch values at the nodes (a, c) x (along_m, range_m), bilinear between them: no
      // patch edges in the image.
      const auto node = [&](std::uint64_t c) {
        return (1.0 - wa) * value(row0, c) + wa * value(row1, c);
      };
      std::uint64_t last_cell = 0;
      bool have = false;
      double lo = 1.0, hi = 1.0;
      for (std::size_t i = from; i < to; ++i) {
        // Where the echo is 30 dB or more above the term, its texture cannot show (a node of
        // T = 10, 1 % of them for nu = 0.2, adds 1 %): the term at its mean, without the look-ups.
        if (mean[i] > 1000.0 * level[i]) {
          mean[i] += level[i];
          continue;
        }
        const double ur = (static_cast<double>(i) + 0.5) * inv_patch;
        const double fr = std::floor(ur);
        const auto cell = static_cast<std::uint64_t>(fr);
        if (!have || cell != last_cell) {
          lo = have && cell == last_cell + 1 ? hi : node(cell);
          hi = node(cell + 1);
          last_cell = cell;
          have = true;
        }
        const double wr = ur - fr;
        const double tex = (1.0 - wr) * lo + wr * hi;
        mean[i] += level[i] * tex;
      }
    };
    add_textured(tables.volume, 0, nv, m.volume_texture_nu, m.volume_patch_along_m,
                 m.volume_patch_range_m, 0x51, tables.volume_cells);
    if (first < nf) {
      add_textured(tables.fill, first, nf, m.fill_texture_nu, m.fill_patch_along_m,
                   m.fill_patch_range_m, 0xf1, tables.fill_cells);
    }
  }
  if (!have_altitude || !(m.first_return_rho > 0.0)) return;
  // The first return depends on the altitude (and the beam's depression) alone: recomputed when
  // they change, else the last ping's.
  SensorMeanTables::FirstReturn& fr = tables.first_return;
  if (!(fr.altitude_m == altitude_m && fr.axis_depression_rad == axis_depression_rad &&
        fr.samples == n)) {
    first_return_bins(m, side, altitude_m, axis_depression_rad, n, fr);
  }
  for (std::size_t k = 0; k < fr.values.size(); ++k) {
    if (!std::isnan(fr.values[k])) mean[fr.first + k] += fr.values[k];
  }
}

}  // namespace sonarsynth
