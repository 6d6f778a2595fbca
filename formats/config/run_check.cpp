// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/config/run_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <thread>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

// Poses examined per line: enough for a fraction to 0.2 %, cheap next to one rendered ping.
constexpr std::size_t kSamplesPerLine = 512;
// Renderer workspace per sample and side (echo, accumulators, noise keys, truth), bytes.
constexpr double kWorkspaceBytesPerSample = 200.0;
// Seabed profile per grid-line crossing (point, crossing positions, scratch), bytes.
constexpr double kProfileBytesPerCrossing = 48.0;
// Mosaic accumulators per pixel (sums, counts, nearest values, labels, output), bytes.
constexpr double kMosaicMemoryBytesPerPixel = 40.0;
// Mosaic files per pixel: float intensity, RGBA display copy, int32 truth, uint8 class and uint32
// instance labels (docs/labels.md), uncompressed, the first three with overviews (a third more).
constexpr double kMosaicFileBytesPerPixel = 21.0;
// Truth waterfall per sample (class, object id, grazing angle) and the class and instance label
// rasters (docs/labels.md), compressed.
constexpr double kTruthBytesPerSample = 14.0;

std::string num(double v, int precision = 6) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", precision, v);
  return buf;
}

std::string percent(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f %%", 100.0 * fraction);
  return buf;
}

std::string gb(double bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g GB", bytes / 1e9);
  return buf;
}

// "east a .. b m, north c .. d m" relative to `origin` (the grid centre, as east_m/north_m).
std::string extent(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                   const Eigen::Vector2d& origin) {
  const Eigen::Vector2d a = lo - origin, b = hi - origin;
  return "east " + num(a.x(), 6) + " .. " + num(b.x(), 6) + " m, north " + num(a.y(), 6) + " .. " +
         num(b.y(), 6) + " m";
}

// The nearest existing directory at or above `p` (where the output will be created).
fs::path existing_ancestor(const fs::path& p) {
  std::error_code ec;
  fs::path a = fs::absolute(p, ec).parent_path();
  while (!a.empty() && !fs::exists(a, ec)) {
    if (a == a.parent_path()) break;
    a = a.parent_path();
  }
  return a;
}

// The pings of the survey, from the line lengths alone (before the Survey counts them in
// integers); throws if they exceed limits.max_pings.
double checked_ping_count(const std::string& file, const SimulationSetup& setup) {
  const SonarConfig& sonar = setup.config.sonar;
  const VehicleConfig& v = setup.vehicle;
  const RunLimits& limits = setup.limits;
  const double period_s = sonar.effective_ping_period_s();
  const double spacing_m = v.speed_m_s * period_s;
  double total_pings = 0.0, worst = -1.0;
  std::size_t worst_line = 0;
  for (std::size_t i = 0; i < setup.lines.size(); ++i) {
    const double n = std::floor(setup.lines[i].length_m() / spacing_m) + 1.0;
    total_pings += n;
    if (n > worst) {
      worst = n;
      worst_line = i;
    }
  }
  if (!(total_pings <= static_cast<double>(limits.max_pings))) {
    const SurveyLine& l = setup.lines[worst_line];
    throw InputError(
        file + ": the survey would render " + num(total_pings, 4) + " pings, more than " +
        "limits.max_pings = " + std::to_string(limits.max_pings) + " (line '" + l.name + "': " +
        num(l.length_m(), 4) + " m at survey.speed_m_s = " + num(v.speed_m_s) + " x ping period " +
        num(period_s) + " s = " + num(spacing_m, 4) + " m between pings). Violated constraint: " +
        "total pings <= limits.max_pings; raise limits.max_pings in the scene file if intended");
  }

  return total_pings;
}

// The output bytes and memory of the run (into `plan`); throws if they exceed the limits or the
// free disk space under `out_dir`.
void check_output_and_memory(const std::string& file, const SimulationSetup& setup,
                             const ProductPlan& products, const fs::path& out_dir,
                             double total_pings, RunPlan& plan) {
  const SonarConfig& sonar = setup.config.sonar;
  const HeightGrid& seabed = setup.scene.bathymetry;
  const RunLimits& limits = setup.limits;
  const double samples = static_cast<double>(sonar.samples_per_channel);
  double bytes = 0.0;  // each format's own estimate (formats/<codec>/format.cpp)
  for (const SonarFormat* f : sonar_formats()) {
    if (!setup.writes_format(f->name)) continue;
    bytes += f->estimated_bytes(sonar, setup.sample_format, total_pings, setup.lines.size());
  }
  if (products.waterfalls) bytes += total_pings * 2.0 * samples;
  if (products.truth) bytes += total_pings * 2.0 * samples * kTruthBytesPerSample;
  double mosaic_pixels = 0.0;
  const Eigen::Vector4d bb = seabed.bounds();
  if (products.mosaic) {
    Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
    for (const SurveyLine& l : setup.lines) {
      for (const Eigen::Vector2d& p : l.waypoints_xy_m) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    }
    const Eigen::Vector2d r = Eigen::Vector2d::Constant(sonar.max_range_m);
    lo = (lo - r).cwiseMax(Eigen::Vector2d(bb[0], bb[1]));
    hi = (hi + r).cwiseMin(Eigen::Vector2d(bb[2], bb[3]));
    if (lo.x() < hi.x() && lo.y() < hi.y()) {
      mosaic_pixels = std::ceil((hi.x() - lo.x()) / products.mosaic_pixel_m + 1.0) *
                      std::ceil((hi.y() - lo.y()) / products.mosaic_pixel_m + 1.0);
    }
    bytes += mosaic_pixels * kMosaicFileBytesPerPixel;
  }
  const GridGeometry& g = seabed.geometry();
  // Grid lines a ray within range crosses (HeightGrid::profile: only the grid's own lines).
  const double crossings =
      std::min(sonar.max_range_m / std::abs(g.dx_m), static_cast<double>(g.cols)) +
      std::min(sonar.max_range_m / std::abs(g.dy_m), static_cast<double>(g.rows)) + 2.0;
  const double threads = setup.config.threads > 0
                             ? setup.config.threads
                             : std::max(1u, std::thread::hardware_concurrency());
  const double per_thread =
      2.0 * samples * kWorkspaceBytesPerSample +
      crossings *
          // A bicubic seabed is sampled at up to 8 points per crossing (HeightGrid::profile).
          (seabed.interpolation() == Interpolation::kBicubic
               ? std::max(setup.config.quality.profile.grid_subdivisions,
                          HeightGrid::kBicubicSegmentsPerCell)
               : setup.config.quality.profile.grid_subdivisions) *
          kProfileBytesPerCrossing;
  const double memory = threads * per_thread + mosaic_pixels * kMosaicMemoryBytesPerPixel;
  // Both messages name the mosaic, where the run makes one.
  const std::string mosaic_text = products.mosaic ? ", a mosaic of " + num(mosaic_pixels, 4) +
                                                        " pixels at --res " +
                                                        num(products.mosaic_pixel_m) + " m"
                                                  : "";
  if (!(bytes <= limits.max_output_gb * 1e9)) {
    throw InputError(file + ": the run would write about " + gb(bytes) + " (" +
                     num(total_pings, 4) + " pings of " + num(samples) + " samples per side" +
                     mosaic_text +
                     "), more than limits.max_output_gb = " + num(limits.max_output_gb) +
                     ". Violated constraint: estimated output <= limits.max_output_gb; raise "
                     "limits.max_output_gb in the scene file if intended");
  }
  if (!(memory <= limits.max_memory_gb * 1e9)) {
    throw InputError(file + ": the run would need about " + gb(memory) + " of memory (" +
                     num(threads) + " thread(s) x " + gb(per_thread) + " for " + num(samples) +
                     " samples and " + num(crossings, 4) + " grid cells within range (cell " +
                     num(std::abs(g.dx_m)) + " x " + num(std::abs(g.dy_m)) + " m)" + mosaic_text +
                     "), more than limits.max_memory_gb = " + num(limits.max_memory_gb) +
                     ". Violated constraint: estimated memory <= limits.max_memory_gb; raise "
                     "limits.max_memory_gb in the scene file if intended");
  }
  plan.output_bytes = static_cast<std::uint64_t>(bytes);
  plan.memory_bytes = static_cast<std::uint64_t>(memory);
  {
    const fs::path where = existing_ancestor(out_dir);
    std::error_code ec;
    const fs::space_info sp = fs::space(where, ec);
    if (!ec && static_cast<double>(sp.available) < bytes) {
      throw InputError(file + ": the run would write about " + gb(bytes) + " but " +
                       where.string() + " has " + gb(static_cast<double>(sp.available)) +
                       " free. Violated constraint: estimated output <= free disk space");
    }
  }
}

// Line `i` of the survey (its first ping `first`) over valid seabed, the sensor between seabed
// and surface, range > altitude: throws if not, else its check (warnings into `plan`).
LineCheck check_line(const std::string& file, const SimulationSetup& setup, const Survey& survey,
                     std::size_t i, std::uint64_t first, RunPlan& plan) {
  const SonarConfig& sonar = setup.config.sonar;
  const VehicleConfig& v = setup.vehicle;
  const HeightGrid& seabed = setup.scene.bathymetry;
  const Eigen::Vector4d bb = seabed.bounds();
  const SurveyLine& l = survey.line(i);
  LineCheck lc;
  lc.name = l.name;
  lc.pings = survey.pings_in_line(i);
  const std::size_t k =
      static_cast<std::size_t>(std::min<std::uint64_t>(lc.pings, kSamplesPerLine));
  std::size_t over = 0, short_range = 0, above_surface = 0, below_seabed = 0, dry = 0;
  double min_altitude = INFINITY, max_seabed_z = -INFINITY, min_sensor_z = INFINITY;
  double max_sensor_z = -INFINITY;
  Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  for (std::size_t j = 0; j < k; ++j) {
    const std::uint64_t in_line =
        k == 1 ? 0
               : static_cast<std::uint64_t>(
                     std::llround(static_cast<double>(j) * static_cast<double>(lc.pings - 1) /
                                  static_cast<double>(k - 1)));
    const PingPose p = survey.pose(first + in_line, seabed);
    lo = lo.cwiseMin(p.sensor_xy_m);
    hi = hi.cwiseMax(p.sensor_xy_m);
    const double z = seabed.height_m(p.sensor_xy_m.x(), p.sensor_xy_m.y());
    if (std::isnan(z)) continue;
    ++over;
    const double alt = p.sensor_z_m - z;
    if (z > 0.0) ++dry;
    if (p.sensor_z_m > 0.0) ++above_surface;
    if (!(alt > 0.0)) ++below_seabed;
    if (alt > 0.0 && sonar.max_range_m <= alt) ++short_range;
    min_altitude = std::min(min_altitude, alt);
    max_seabed_z = std::max(max_seabed_z, z);
    min_sensor_z = std::min(min_sensor_z, p.sensor_z_m);
    max_sensor_z = std::max(max_sensor_z, p.sensor_z_m);
  }
  lc.sampled = k;
  lc.seabed_fraction = static_cast<double>(over) / static_cast<double>(k);
  lc.short_range_fraction = over ? static_cast<double>(short_range) / static_cast<double>(over) : 0;
  const std::string where = file + ": survey line '" + l.name + "'";
  const Eigen::Vector2d centre(0.5 * (bb[0] + bb[2]), 0.5 * (bb[1] + bb[3]));
  const std::string extents = "the sensor track spans " + extent(lo, hi, centre) +
                              "; the bathymetry grid spans " +
                              extent({bb[0], bb[1]}, {bb[2], bb[3]}, centre) +
                              " (metres from the grid's centre, as east_m/north_m)";
  if (over == 0) {
    throw InputError(where + ": no ping is over valid seabed (" + extents +
                     "). Violated constraint: every line crosses the bathymetry");
  }
  auto frac = [&](std::size_t n) {
    return percent(static_cast<double>(n) / static_cast<double>(over));
  };
  if (dry > 0) {
    throw InputError(where + ": the seabed is above sea level (height up to " +
                     num(max_seabed_z, 4) + " m) under " + frac(dry) +
                     " of its pings over seabed. Violated constraint: bathymetry heights < 0 "
                     "(the sea surface is height 0; see bathymetry.depth_positive_down)");
  }
  if (above_surface > 0) {
    const std::string key = v.depth_mode == VehicleConfig::DepthMode::kAltitude
                                ? "survey.altitude_m = " + num(v.altitude_m)
                                : "survey.depth_m = " + num(v.depth_m);
    throw InputError(where + ": " + key + " puts the sensor above the sea surface (height up to " +
                     num(max_sensor_z, 4) + " m) on " + frac(above_surface) +
                     " of its pings over seabed. Violated constraint: sensor below the surface "
                     "(altitude smaller than the water depth)");
  }
  if (below_seabed > 0) {
    const std::string key =
        v.depth_mode == VehicleConfig::DepthMode::kDepth
            ? "survey.depth_m = " + num(v.depth_m)
            : "survey.lever_arm_m / altitude_time_constant_s / disturbance.heave_m / "
              "disturbance.altitude_m";
    throw InputError(where + ": " + key + " puts the sensor below the seabed (altitude down to " +
                     num(min_altitude, 4) + " m) on " + frac(below_seabed) +
                     " of its pings over seabed. Violated constraint: sensor above the seabed");
  }
  if (short_range == over) {
    throw InputError(where + ": " + setup.range_key + " = " + num(sonar.max_range_m) +
                     " m is not longer than the sensor's altitude (at least " +
                     num(min_altitude, 4) +
                     " m): every ping would be empty. Violated "
                     "constraint: range > altitude");
  }
  if (short_range > 0) {
    plan.warnings.push_back("survey line '" + l.name + "': on " + frac(short_range) +
                            " of its pings the altitude exceeds " + setup.range_key + " = " +
                            num(sonar.max_range_m) + " m (those pings see no seabed)");
  }
  if (over < k) {
    plan.warnings.push_back(
        "survey line '" + l.name + "': " + percent(1.0 - lc.seabed_fraction) +
        " of its pings are not over valid seabed (" + extents +
        "); they are written with altitude 0 (no seabed) and counted by `sonarsynth info`");
  }
  return lc;
}

}  // namespace

RunPlan check_simulation(const std::string& scene_path, const SimulationSetup& setup,
                         const ProductPlan& products, const fs::path& out_dir) {
  const std::string& file = scene_path;
  RunPlan plan;
  if (products.mosaic &&
      !(products.mosaic_pixel_m > 0.0 && std::isfinite(products.mosaic_pixel_m))) {
    throw InputError("--res = " + num(products.mosaic_pixel_m) +
                     ". Violated constraint: mosaic pixel size > 0 (metres)");
  }

  const double total_pings = checked_ping_count(file, setup);
  plan.total_pings = static_cast<std::uint64_t>(total_pings);
  check_output_and_memory(file, setup, products, out_dir, total_pings, plan);

  // Every line over valid seabed, the sensor between seabed and surface, range > altitude.
  const Survey survey = setup.make_survey();
  std::uint64_t first = 0;
  for (std::size_t i = 0; i < survey.line_count(); ++i) {
    plan.lines.push_back(check_line(file, setup, survey, i, first, plan));
    first += plan.lines.back().pings;
  }
  return plan;
}

void RunStatistics::ping(const RenderedPing& ping) {
  if (current_ >= lines_.size()) return;
  Line& l = lines_[current_];
  ++l.pings;
  for (const SideOutput* s : {&ping.port, &ping.starboard}) {
    l.samples += s->samples.size();
    l.saturated += s->saturated;
    l.invalid += s->invalid;
  }
  if (!(std::isfinite(ping.pose.altitude_m) && ping.pose.altitude_m > 0.0)) ++l.no_seabed_pings;
}

std::vector<std::string> RunStatistics::warnings(const std::vector<std::string>& names,
                                                 double max_value, double gain_db,
                                                 double max_fraction) const {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < lines_.size(); ++i) {
    const Line& l = lines_[i];
    const std::string name = i < names.size() ? names[i] : std::to_string(i + 1);
    const double n = static_cast<double>(std::max<std::uint64_t>(l.samples, 1));
    if (static_cast<double>(l.saturated) > max_fraction * n) {
      const std::string why =
          std::isnan(gain_db)
              ? " (output.normalise: per_ping_max puts each ping's largest noise-free sample at "
                "full scale: the noise takes the brightest samples above it)"
              : " with gain " + num(gain_db, 4) +
                    " dB (lower output.gain_db, or leave it out for the automatic gain)";
      out.push_back("survey line '" + name + "': " + percent(static_cast<double>(l.saturated) / n) +
                    " of the samples (" + std::to_string(l.saturated) + ") are saturated at " +
                    num(max_value) + why);
    }
    if (static_cast<double>(l.invalid) > max_fraction * n) {
      out.push_back("survey line '" + name + "': " + percent(static_cast<double>(l.invalid) / n) +
                    " of the samples (" + std::to_string(l.invalid) +
                    ") overflowed to a non-finite value and were written as 0 (gain " +
                    num(gain_db, 4) + " dB)");
    }
    if (l.no_seabed_pings > 0) {
      out.push_back("survey line '" + name + "': " + std::to_string(l.no_seabed_pings) + " of " +
                    std::to_string(l.pings) +
                    " pings have no seabed under the sensor (written with altitude 0)");
    }
  }
  return out;
}

}  // namespace sonarsynth
