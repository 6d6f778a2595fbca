// SPDX-License-Identifier: MIT
// mosaic_files(): what `sonarsynth mosaic` and sonarsynth.mosaic() do, checks to summary.
#include "sonarsynth/formats/products/mosaic_files.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <system_error>
#include <utility>

#include "sonarsynth/enum_names.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/raster/gdal_grid.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

constexpr EnumName<MosaicRule> kRuleNames[] = {{MosaicRule::weighted_mean, "mean"},
                                               {MosaicRule::max, "max"},
                                               {MosaicRule::nearest, "nearest"}};

/// "(x, y)" of a local point in the frame's projected coordinates, to 0.1 m.
std::string projected_text(const GeoFrame& frame, double x, double y) {
  const Eigen::Vector2d p = frame.projected_from_local({x, y});
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(1);
  os << "(" << p.x() << ", " << p.y() << ")";
  return os.str();
}

/// With a bathymetry, a ping places nothing where its swath misses the grid: says so when no
/// ping was gridded because the grid and the survey do not overlap at all.
void refuse_disjoint_bathymetry(const MosaicRequest& q, const XtfMosaicResult& r,
                                const LoadedGrid& bathy) {
  const GridGeometry& m = r.image.geometry;
  const double half_x = 0.5 * m.dx_m, half_y = 0.5 * std::abs(m.dy_m);
  const double mx0 = m.x_of_col(0) - half_x;
  const double mx1 = m.x_of_col(static_cast<double>(m.cols) - 1.0) + half_x;
  const double my_a = m.y_of_row(0), my_b = m.y_of_row(static_cast<double>(m.rows) - 1.0);
  const double my0 = std::min(my_a, my_b) - half_y, my1 = std::max(my_a, my_b) + half_y;
  const Eigen::Vector4d bb = bathy.grid.bounds();
  if (bb[2] < mx0 || bb[0] > mx1 || bb[3] < my0 || bb[1] > my1) {
    throw InputError(
        q.names.bathymetry + " " + q.bathymetry.string() + ": the grid " +
        projected_text(r.frame, bb[0], bb[1]) + " .. " + projected_text(r.frame, bb[2], bb[3]) +
        " does not overlap the survey " + projected_text(r.frame, mx0, my0) + " .. " +
        projected_text(r.frame, mx1, my1) + " (EPSG:" + std::to_string(r.frame.epsg()) +
        " metres): no ping could be gridded");
  }
}

/// `head` then the first `examples` of `total`, one per indented line, and how many more.
std::string with_examples(std::string head, const std::vector<std::string>& examples,
                          std::uint64_t total) {
  for (const std::string& e : examples) head += "\n  " + e;
  if (examples.size() < total) {
    head += "\n  ... (" + std::to_string(total - examples.size()) + " more)";
  }
  return head;
}

/// The warnings of a gridding, in the order `sonarsynth mosaic` has always printed them.
std::vector<std::string> gridding_warnings(const XtfMosaicResult& r, AltitudeSource source) {
  std::vector<std::string> w;
  const auto n = [](std::uint64_t v) { return std::to_string(v); };
  if (r.pings_dropped > 0) {
    w.push_back(with_examples("dropped " + n(r.pings_dropped) + " of " + n(r.pings) +
                                  " pings as navigation outliers (" + n(r.dropped_position_jump) +
                                  " position jumps, " + n(r.dropped_slant_range) +
                                  " slant ranges, " + n(r.dropped_heading) + " headings):",
                              r.dropped_examples, r.pings_dropped));
  }
  if (r.reader_anomalies > 0) {
    w.push_back(with_examples(n(r.reader_anomalies) +
                                  " anomalies while reading (malformed packets skipped; see "
                                  "sonarsynth info):",
                              r.reader_anomaly_messages, r.reader_anomalies));
  }
  if (r.pings_no_navigation > 0) {
    w.push_back("skipped " + n(r.pings_no_navigation) + " of " + n(r.pings) +
                " pings with missing or zero navigation");
  }
  if (r.pings_no_samples > 0) {
    w.push_back("skipped " + n(r.pings_no_samples) + " pings without port/starboard samples");
  }
  if (r.pings_no_altitude > 0) {
    w.push_back("skipped " + n(r.pings_no_altitude) + " pings without altitude");
  }
  if (r.pings_tracked_altitude > 0 && source == AltitudeSource::kAuto) {
    w.push_back("altitude of " + n(r.pings_tracked_altitude) + " of " +
                n(r.pings_tracked_altitude + r.pings_header_altitude) +
                " gridded pings tracked from the first bottom return (" +
                n(r.pings_header_disagreed) +
                " where the header altitude disagreed, the others "
                "without one)");
  }
  return w;
}

/// The checks made before any file is read: outputs distinct, not inputs, not existing unless
/// overwrite; options valid.
void check_request(const MosaicRequest& q) {
  if (q.inputs.empty()) {
    throw InputError("no input file. Violated constraint: at least one sonar file");
  }
  q.options.validate();
  const std::string output = q.output.string(), rgb = q.write.rgb_path;
  refuse_equal_outputs({output, rgb}, {q.names.output, q.names.rgb});
  std::vector<std::string> inputs;
  for (const fs::path& p : q.inputs) inputs.push_back(p.string());
  inputs.push_back(q.bathymetry.string());
  refuse_output_over_input({output, rgb}, inputs);
  q.write.validate();  // display copy name, creation options: before the (long) gridding
  for (const std::string& p : {output, rgb}) {
    if (!p.empty() && !q.write.overwrite && fs::exists(p)) {
      throw InputError("output " + p + " already exists (use --overwrite to replace it)");
    }
  }
  if (q.bathymetry.empty() && q.bathymetry_depth_positive) {
    throw InputError(q.names.depth_positive + " given without " + q.names.bathymetry +
                     ". Violated constraint: " + q.names.depth_positive + " describes the " +
                     q.names.bathymetry + " grid");
  }
}

}  // namespace

MosaicRule parse_mosaic_rule(const std::string& text, const std::string& what) {
  return parse_enum(kRuleNames, text, what);
}

const char* to_string(MosaicRule rule) {
  return enum_name(kRuleNames, rule);
}

std::string MosaicSummary::text() const {
  const GridGeometry& g = result.image.geometry;
  std::ostringstream os;
  os << "wrote " << output.string() << ": " << g.cols << " x " << g.rows << " pixels of "
     << pixel_size_m << " m, EPSG:" << result.frame.epsg() << ", " << result.pings_gridded << " of "
     << result.pings << " pings, " << result.samples_placed << " samples (" << result.fill_points
     << " fill points); altitude: " << result.pings_header_altitude << " header, "
     << result.pings_tracked_altitude << " tracked";
  if (!rgb_path.empty()) os << "; display copy " << rgb_path.string();
  return os.str();
}

MosaicSummary mosaic_files(const MosaicRequest& request) {
  check_request(request);
  MosaicSummary s;
  const auto warn = [&](std::string w) {
    if (request.on_warning) request.on_warning(w);
    s.warnings.push_back(std::move(w));
  };
  std::optional<LoadedGrid> bathy;
  if (!request.bathymetry.empty()) {
    GridReadOptions ro;
    ro.depth_positive_down = request.bathymetry_depth_positive;
    bathy = read_height_grid(request.bathymetry.string(), ro);
  }
  const XtfMosaicOptions& mo = request.options;
  s.result = mosaic_xtf(request.inputs, mo, bathy ? &*bathy : nullptr);
  const XtfMosaicResult& r = s.result;
  for (const std::string& m : r.skipped_files) warn("skipped " + m);
  if (r.pings_gridded == 0 && bathy) refuse_disjoint_bathymetry(request, r, *bathy);
  if (r.pings_gridded == 0) {
    std::string names;
    for (const fs::path& f : request.inputs) names += (names.empty() ? "" : ", ") + f.string();
    throw FormatError(names + ": no ping could be gridded (" + std::to_string(r.pings) +
                      " pings, " + std::to_string(r.pings_no_navigation) + " without navigation, " +
                      std::to_string(r.pings_no_altitude) + " without altitude)");
  }
  for (std::string& w : gridding_warnings(r, mo.altitude_source)) warn(std::move(w));

  MosaicWriteOptions wo = request.write;
  wo.metadata.push_back({"SONARSYNTH_MOSAIC_RULE", to_string(mo.gridding.rule)});
  wo.metadata.push_back({"SONARSYNTH_ALTITUDE_SOURCE", to_string(mo.altitude_source)});
  wo.metadata.push_back({"SONARSYNTH_GAIN_NORMALISATION", to_string(mo.gain_normalisation)});
  const std::string output = request.output.string();
  try {
    write_mosaic(output, r.frame, r.image, wo);
  } catch (const std::system_error& e) {
    // The display copy is written on a thread of its own, alongside the mosaic.
    if (e.code() != std::errc::resource_unavailable_try_again || wo.rgb_path.empty()) throw;
    throw FormatError(output + ": could not start the thread that writes the display copy " +
                      wo.rgb_path + " (" + e.code().message() +
                      "; the limit on threads, ulimit -u, or on address space, ulimit -v, is "
                      "reached); nothing written (--no-rgb needs no thread)");
  }
  // The pixels are in the files now; the geometry stays for the summary.
  s.result.image.intensity = {};
  s.result.image.count = {};
  s.result.image.labels = {};
  s.output = request.output;
  s.rgb_path = wo.rgb_path;
  s.pixel_size_m = mo.pixel_size_m;
  return s;
}

}  // namespace sonarsynth
