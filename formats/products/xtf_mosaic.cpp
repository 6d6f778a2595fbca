// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/products/xtf_mosaic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <utility>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"

namespace sonarsynth {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Neighbours on each side of a ping in the position-jump test, and how many dropped pings and
// reader anomalies are described in the result.
constexpr std::size_t kJumpWindow = 5;
constexpr std::size_t kMaxExamples = 10;

struct NavPoint {
  Geodetic position;
  double margin_m = 0.0;  ///< slant range (+ layback if applied): how far samples can reach
  double slant_range_m = 0.0;
  float heading_true_deg = 0.0f;  ///< SensorHeading as stored (true)
  std::uint32_t ping_number = 0;
  std::uint64_t packet_index = 0;
  Eigen::Vector2d xy{0.0, 0.0};  ///< in the provisional frame
  bool dropped = false;
};

struct FileNav {
  std::vector<NavPoint> points;
  std::vector<std::uint64_t> dropped_packets;  ///< ascending
  std::vector<double> tracked_m;  ///< tracked altitude of each ping with samples, in file order
  bool skipped = false;           ///< no ping has port or starboard samples
};

double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// Component-wise median of xy over points[idx[first..last)].
Eigen::Vector2d median_xy(const std::vector<NavPoint>& points, const std::vector<std::size_t>& idx,
                          std::size_t first, std::size_t last) {
  std::vector<double> xs, ys;
  for (std::size_t k = first; k < last; ++k) {
    xs.push_back(points[idx[k]].xy.x());
    ys.push_back(points[idx[k]].xy.y());
  }
  return {median(xs), median(ys)};
}

/// Latitude and longitude medians (longitudes unwrapped around the first one): a centre that a
/// few wild positions cannot move.
Geodetic robust_centre(const std::vector<FileNav>& nav) {
  std::vector<double> lats, dlons;
  double lon0 = kNaN;
  for (const FileNav& f : nav) {
    for (const NavPoint& p : f.points) {
      if (std::isnan(lon0)) lon0 = p.position.lon_rad;
      lats.push_back(p.position.lat_rad);
      dlons.push_back(std::remainder(p.position.lon_rad - lon0, 2.0 * kPi));
    }
  }
  return {median(lats), std::remainder(lon0 + median(dlons), 2.0 * kPi), 0.0};
}

std::string describe(const std::string& file, const NavPoint& p) {
  std::ostringstream os;
  os.precision(7);
  os << file << ": ping " << p.ping_number << " (packet " << p.packet_index << ") at lat "
     << deg_from_rad(p.position.lat_rad) << ", lon " << deg_from_rad(p.position.lon_rad);
  return os.str();
}

/// Marks the navigation outliers of one file (see mosaic_xtf()) and counts them in `result`.
void drop_outliers(const std::string& file, FileNav& f, const GeoFrame& provisional,
                   const XtfMosaicOptions& options, XtfMosaicResult& result) {
  std::vector<NavPoint>& pts = f.points;
  if (pts.empty()) return;
  const auto drop = [&](NavPoint& p, std::size_t& counter, const std::string& why) {
    p.dropped = true;
    ++counter;
    ++result.pings_dropped;
    if (result.dropped_examples.size() < kMaxExamples) {
      result.dropped_examples.push_back(describe(file, p) + ": " + why);
    }
  };
  std::vector<double> ranges;
  for (const NavPoint& p : pts) ranges.push_back(p.slant_range_m);
  const double median_range = median(ranges);
  std::vector<std::size_t> located;  // pings with a position in the provisional frame
  for (std::size_t i = 0; i < pts.size(); ++i) {
    NavPoint& p = pts[i];
    std::ostringstream os;
    os.precision(6);
    if (!std::isfinite(p.heading_true_deg)) {
      os << "SensorHeading = " << p.heading_true_deg;
      drop(p, result.dropped_heading, os.str());
    } else if (p.slant_range_m > options.max_slant_range_ratio * median_range) {
      os << "SlantRange = " << p.slant_range_m << " m, more than " << options.max_slant_range_ratio
         << " x the file's median " << median_range << " m";
      drop(p, result.dropped_slant_range, os.str());
    }
    try {
      p.xy = provisional.local_from_geodetic(p.position);
      located.push_back(i);
    } catch (const InputError&) {
      if (!p.dropped) {
        drop(p, result.dropped_position_jump,
             "position cannot be projected in the zone of the survey (EPSG:" +
                 std::to_string(provisional.epsg()) + ")");
      }
    }
  }
  // Position jumps among the located pings, in file order.
  std::vector<double> steps;
  for (std::size_t k = 1; k < located.size(); ++k) {
    steps.push_back((pts[located[k]].xy - pts[located[k - 1]].xy).norm());
  }
  const double step = steps.empty() ? 0.0 : median(steps);
  const double threshold = std::max(median_range, 2.0 * static_cast<double>(kJumpWindow) * step);
  const std::size_t n = located.size();
  for (std::size_t k = 0; k < n; ++k) {
    NavPoint& p = pts[located[k]];
    const std::size_t b0 = k >= kJumpWindow ? k - kJumpWindow : 0;
    const std::size_t a1 = std::min(n, k + 1 + kJumpWindow);
    const bool has_before = b0 < k;
    const bool has_after = k + 1 < a1;
    if (!has_before && !has_after) continue;
    const double d_before = has_before ? (p.xy - median_xy(pts, located, b0, k)).norm() : kNaN;
    const double d_after = has_after ? (p.xy - median_xy(pts, located, k + 1, a1)).norm() : kNaN;
    if ((!has_before || d_before > threshold) && (!has_after || d_after > threshold)) {
      if (p.dropped) continue;
      std::ostringstream os;
      os.precision(6);
      os << "position jumps away from the pings around it:";
      if (has_before) os << " " << d_before << " m from the median of the " << k - b0 << " before";
      if (has_after) {
        os << (has_before ? "," : "") << " " << d_after << " m from the median of the "
           << a1 - k - 1 << " after";
      }
      os << " (threshold " << threshold << " m)";
      drop(p, result.dropped_position_jump, os.str());
    }
  }
  for (const NavPoint& p : pts) {
    if (p.dropped) f.dropped_packets.push_back(p.packet_index);
  }
}

bool has_samples(const SonarPing& s) {
  return (!s.port.empty() || !s.starboard.empty()) && s.slant_range_m > 0.0 &&
         std::isfinite(s.slant_range_m);
}

}  // namespace

void XtfMosaicOptions::validate() const {
  if (!(pixel_size_m > 0.0) || !std::isfinite(pixel_size_m)) {
    std::ostringstream os;
    os << "xtf mosaic: pixel_size_m (--res) = " << pixel_size_m
       << ". Violated constraint: pixel_size_m > 0";
    throw InputError(os.str());
  }
  if (max_pixels == 0) {
    throw InputError("xtf mosaic: max_pixels (--max-pixels) = 0. Violated constraint: > 0");
  }
  if (!(max_slant_range_ratio > 1.0)) {
    std::ostringstream os;
    os << "xtf mosaic: max_slant_range_ratio = " << max_slant_range_ratio
       << ". Violated constraint: max_slant_range_ratio > 1";
    throw InputError(os.str());
  }
  gridding.validate();
}

std::vector<double> track_file_altitudes(const std::filesystem::path& file,
                                         const BottomTrackOptions& options) {
  BottomTracker tracker(options);
  const std::unique_ptr<SideScanSource> reader = SideScanSource::open(file);
  SideScanRecord rec;
  while (reader->next(rec)) {
    if (!has_samples(rec.sonar)) continue;
    tracker.add_ping(rec.sonar.port, rec.sonar.starboard, rec.sonar.slant_range_m);
  }
  return tracker.altitudes_m();
}

namespace {

/// Pass 1: the navigation of every file (positions, margins, tracked altitudes); files without
/// any port/starboard channel are skipped and named in result.skipped_files. Throws
/// FormatError if every file is skipped.
std::vector<FileNav> read_navigation(const std::vector<std::filesystem::path>& files,
                                     const XtfMosaicOptions& options, XtfMosaicResult& result) {
  std::vector<FileNav> nav(files.size());
  SideScanRecord rec;
  for (std::size_t fi = 0; fi < files.size(); ++fi) {
    const auto& path = files[fi];
    const std::unique_ptr<SideScanSource> reader = SideScanSource::open(path);
    BottomTracker tracker(options.tracking);
    std::size_t with_samples = 0;
    std::size_t pings = 0;
    while (reader->next(rec)) {
      ++pings;
      const SonarPing& s = rec.sonar;
      if (!has_samples(s)) continue;
      ++with_samples;
      tracker.add_ping(s.port, s.starboard, s.slant_range_m);
      if (!rec.nav_valid) continue;
      const double layback = rec.layback_m;
      const double margin = options.apply_layback && std::isfinite(layback) && layback > 0.0
                                ? s.slant_range_m + layback
                                : s.slant_range_m;
      NavPoint p;
      p.position = s.sensor_position;
      p.margin_m = margin;
      p.slant_range_m = s.slant_range_m;
      p.heading_true_deg = static_cast<float>(rec.heading_true_deg);
      p.ping_number = s.ping_number;
      p.packet_index = rec.index;
      nav[fi].points.push_back(p);
    }
    if (with_samples == 0) {
      nav[fi].skipped = true;
      result.skipped_files.push_back(path.string() + ": no sonar channel (no ping of " +
                                     std::to_string(pings) + " has port or starboard samples)");
      continue;
    }
    nav[fi].tracked_m = tracker.altitudes_m();
  }
  if (result.skipped_files.size() == files.size()) {
    std::string all;
    for (const std::string& m : result.skipped_files) all += (all.empty() ? "" : "; ") + m;
    throw FormatError("xtf mosaic: nothing usable: " + all);
  }
  return nav;
}

/// The altitude of the k-th ping with samples `s` of a file.
AltitudeChoice altitude_of(const FileNav& nav, std::size_t k, const SonarPing& s,
                           const XtfMosaicOptions& options) {
  const std::vector<double>& tr = nav.tracked_m;
  const double tracked = k < tr.size() ? tr[k] : kNaN;
  const std::size_t n = std::max(s.port.size(), s.starboard.size());
  return choose_altitude(options.altitude_source, s.altitude_m, tracked,
                         s.slant_range_m / static_cast<double>(n), options.tracking);
}

/// Across-track gain statistics over all the files (docs/conversion.md); finished.
void gather_gain(const std::vector<std::filesystem::path>& files, const std::vector<FileNav>& nav,
                 const XtfMosaicOptions& options, GainNormaliser& gain) {
  if (options.gain_normalisation != GainNormalisation::kOff) {
    SideScanRecord rec;
    for (std::size_t fi = 0; fi < files.size(); ++fi) {
      if (nav[fi].skipped) continue;
      const std::unique_ptr<SideScanSource> reader = SideScanSource::open(files[fi]);
      std::size_t k = 0;
      while (reader->next(rec)) {
        const SonarPing& s = rec.sonar;
        if (!has_samples(s)) continue;
        const AltitudeChoice a = altitude_of(nav[fi], k++, s, options);
        gain.add_ping(s.port, s.starboard, s.slant_range_m, a.altitude_m);
      }
    }
  }
  gain.finish();
}

/// The frame of the kept positions (the zone of their centroid, longitude averaged on the
/// circle: dateline-safe; or the bathymetry's) into result.frame, and the extent of their
/// swaths in it (the points are released).
std::pair<Eigen::Vector2d, Eigen::Vector2d> mosaic_extent(std::vector<FileNav>& nav,
                                                          const LoadedGrid* bathymetry,
                                                          XtfMosaicResult& result) {
  double lat = 0.0, sx = 0.0, sy = 0.0;
  std::size_t kept = 0;
  for (const FileNav& f : nav) {
    for (const NavPoint& p : f.points) {
      if (p.dropped) continue;
      lat += p.position.lat_rad;
      sx += std::cos(p.position.lon_rad);
      sy += std::sin(p.position.lon_rad);
      ++kept;
    }
  }
  const Geodetic centroid{lat / static_cast<double>(kept), std::atan2(sy, sx), 0.0};
  result.frame = bathymetry ? bathymetry->frame : GeoFrame::around(centroid);
  Eigen::Vector2d lo(std::numeric_limits<double>::infinity(),
                     std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (FileNav& f : nav) {
    for (const NavPoint& p : f.points) {
      if (p.dropped) continue;
      const Eigen::Vector2d xy = result.frame.local_from_geodetic(p.position);
      lo = lo.cwiseMin((xy.array() - p.margin_m).matrix());
      hi = hi.cwiseMax((xy.array() + p.margin_m).matrix());
    }
    f.points.clear();
    f.points.shrink_to_fit();
  }
  return {lo, hi};
}

/// Pass 2 over one file: every ping with samples, navigation and an altitude gridded.
void grid_file(const std::filesystem::path& file, const FileNav& nav,
               const XtfMosaicOptions& options, const GainNormaliser& gain, MosaicGrid& grid,
               XtfMosaicResult& result) {
  const std::unique_ptr<SideScanSource> reader = SideScanSource::open(file);
  const std::vector<std::uint64_t>& dropped = nav.dropped_packets;
  auto next_dropped = dropped.begin();
  std::size_t k = 0;  // pings with samples so far
  SideScanRecord rec;
  while (reader->next(rec)) {
    ++result.pings;
    SonarPing& s = rec.sonar;
    if (!has_samples(s)) {
      ++result.pings_no_samples;
      continue;
    }
    const AltitudeChoice alt = altitude_of(nav, k++, s, options);
    if (!rec.nav_valid) {
      ++result.pings_no_navigation;
      grid.break_line();
      continue;
    }
    while (next_dropped != dropped.end() && *next_dropped < rec.index) ++next_dropped;
    if (next_dropped != dropped.end() && *next_dropped == rec.index) {
      grid.break_line();  // a navigation outlier (counted in pass 1)
      continue;
    }
    MosaicPing mp;
    mp.sensor_xy_m = result.frame.local_from_geodetic(s.sensor_position);
    mp.heading_grid_rad =
        result.frame.grid_azimuth_from_true_rad(s.heading_true_rad, mp.sensor_xy_m);
    mp.pitch_rad = std::isfinite(s.pitch_rad) && std::abs(s.pitch_rad) < rad_from_deg(45.0)
                       ? s.pitch_rad
                       : 0.0;
    mp.slant_range_m = s.slant_range_m;
    if (options.apply_layback) {
      const double layback = rec.layback_m;
      if (std::isfinite(layback) && layback > 0.0) {
        mp.sensor_xy_m -=
            layback * Eigen::Vector2d(std::sin(mp.heading_grid_rad), std::cos(mp.heading_grid_rad));
      }
    }
    if (std::isnan(alt.altitude_m)) {
      ++result.pings_no_altitude;
      continue;
    }
    if (alt.tracked) {
      ++result.pings_tracked_altitude;
      if (alt.header_disagreed) ++result.pings_header_disagreed;
    } else {
      ++result.pings_header_altitude;
    }
    mp.altitude_m = alt.altitude_m;
    gain.apply(s.port, s.starboard, s.slant_range_m, alt.altitude_m);
    mp.port = std::move(s.port);
    mp.starboard = std::move(s.starboard);
    const MosaicAddStats st = grid.add(mp);
    if (st.samples_placed > 0) ++result.pings_gridded;
    result.samples_placed += st.samples_placed;
    result.fill_points += st.fill_points + st.along_fill_points;
  }
  grid.break_line();  // no along-track fill from one file into the next
  result.reader_anomalies += reader->total_anomalies();
  for (std::string& m : reader->anomaly_messages(kMaxExamples)) {
    if (result.reader_anomaly_messages.size() >= kMaxExamples) break;
    result.reader_anomaly_messages.push_back(std::move(m));
  }
}

}  // namespace

XtfMosaicResult mosaic_xtf(const std::vector<std::filesystem::path>& files,
                           const XtfMosaicOptions& options, const LoadedGrid* bathymetry) {
  options.validate();
  if (files.empty()) throw InputError("xtf mosaic: no input file");
  XtfMosaicResult result;
  result.files = files.size();
  std::vector<FileNav> nav = read_navigation(files, options, result);
  GainNormaliser gain(options.gain_normalisation);
  gather_gain(files, nav, options, gain);
  const auto where = [&] {
    return files.size() == 1 ? files.front().string() : std::to_string(files.size()) + " files";
  };
  std::size_t located = 0;
  for (const FileNav& f : nav) located += f.points.size();
  if (located == 0) {
    throw FormatError("xtf mosaic: no ping has valid navigation in " + where() +
                      " (SensorX/Ycoordinate zero, invalid, or not geographic: NavUnits != 3)");
  }

  // Navigation outliers, judged in metres in the zone of a robust centre of all positions.
  const GeoFrame provisional = GeoFrame::around(robust_centre(nav));
  for (std::size_t fi = 0; fi < files.size(); ++fi) {
    if (nav[fi].skipped) continue;
    drop_outliers(files[fi].string(), nav[fi], provisional, options, result);
  }
  if (result.pings_dropped == located) {
    throw FormatError("xtf mosaic: every ping with a position in " + where() + " (" +
                      std::to_string(located) +
                      ") is a navigation outlier; first: " + result.dropped_examples.front());
  }
  const auto [lo, hi] = mosaic_extent(nav, bathymetry, result);
  // The pixel count before anything is allocated (geometry_covering rounds the edges outwards
  // to whole pixels: at most one more on each side).
  const double res = options.pixel_size_m;
  const double cols = std::ceil((hi.x() - lo.x()) / res) + 1.0;
  const double rows = std::ceil((hi.y() - lo.y()) / res) + 1.0;
  if (cols * rows > static_cast<double>(options.max_pixels)) {
    std::ostringstream os;
    os.precision(6);
    os << "xtf mosaic: the mosaic of " << where() << " would be about " << cols << " x " << rows
       << " = " << cols * rows << " pixels (extent " << hi.x() - lo.x() << " x " << hi.y() - lo.y()
       << " m at " << res << " m per pixel), more than max_pixels = " << options.max_pixels
       << ". Violated constraint: pixels <= max_pixels (--max-pixels); "
       << "use a coarser --res or raise --max-pixels";
    throw InputError(os.str());
  }
  const GridGeometry geometry = MosaicGrid::geometry_covering(lo, hi, options.pixel_size_m);
  MosaicGrid grid(geometry, options.gridding, bathymetry ? &bathymetry->grid : nullptr);
  for (std::size_t fi = 0; fi < files.size(); ++fi) {
    if (!nav[fi].skipped) grid_file(files[fi], nav[fi], options, gain, grid, result);
  }
  result.image = grid.finish();
  return result;
}

}  // namespace sonarsynth
