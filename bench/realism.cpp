// SPDX-License-Identifier: MIT
// Realism figures of a side-scan XTF file (definitions in docs/realism.md): seabed
// contrast, water column, shadows, first return, full scale and clipping, along-track correlation
// (measures 1-6, 8); across-track texture, shadow fill and edges, water column statistics,
// first-return profile, far vs near range, near-range clipping, level percentiles, altitude
// (7, 9-16).
// Usage: realism FILE.xtf [--json] [--pings FIRST:END] [--horizontal-beam-deg B]
//   --pings: measure sonar pings FIRST .. END-1 only (0-based, in file order).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "realism_stats.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace xtf = sonarsynth::xtf;
namespace rs = bench::realism;
using sonarsynth::InputError;

namespace {

struct Args {
  std::string path;
  bool json = false;
  std::size_t first_ping = 0;
  std::size_t end_ping = 0;  // 0 = to the end
  double beam_deg = 0.0;     // 0 = from CHANINFO.HorizBeamAngle
};

double parse_number(const std::string& option, const char* text) {
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(v) || v < 0.0)
    throw InputError("realism: option " + option + " = '" + text + "' (need a number >= 0)");
  return v;
}

Args parse_args(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    if (s == "--json") {
      a.json = true;
    } else if (s == "--pings" || s == "--horizontal-beam-deg") {
      if (i + 1 >= argc) throw InputError("realism: option " + s + " needs a value");
      const std::string v = argv[++i];
      if (s == "--horizontal-beam-deg") {
        a.beam_deg = parse_number(s, v.c_str());
        continue;
      }
      const std::size_t colon = v.find(':');
      if (colon == std::string::npos)
        throw InputError("realism: option --pings = '" + v + "' (need FIRST:END)");
      a.first_ping = static_cast<std::size_t>(parse_number(s, v.substr(0, colon).c_str()));
      a.end_ping = static_cast<std::size_t>(parse_number(s, v.substr(colon + 1).c_str()));
      if (a.end_ping <= a.first_ping)
        throw InputError("realism: option --pings = '" + v + "' (need FIRST < END)");
    } else if (!s.empty() && s[0] == '-') {
      throw InputError("realism: unknown option '" + s + "'");
    } else if (a.path.empty()) {
      a.path = s;
    } else {
      throw InputError("realism: more than one file given ('" + a.path + "', '" + s + "')");
    }
  }
  if (a.path.empty())
    throw InputError(
        "usage: realism FILE.xtf [--json] [--pings FIRST:END] [--horizontal-beam-deg B]");
  return a;
}

struct Record {
  std::vector<rs::Ping> pings;
  std::size_t sonar_pings = 0;  // in the file
  double format_max = rs::kNaN;
  double beam_deg = 0.0;
};

/// The largest value of the file's integer sample format; NaN for float formats.
double format_max(const xtf::XtfChanInfo& c) {
  if (c.SampleFormat == 1 || c.SampleFormat == 5) return rs::kNaN;
  const unsigned bits = 8u * c.BytesPerSample;
  if (bits == 0 || bits > 32) return rs::kNaN;
  const bool is_unsigned = c.UniPolar != 0;
  return std::ldexp(1.0, static_cast<int>(is_unsigned ? bits : bits - 1)) - 1.0;
}

Record read_record(const Args& a) {
  xtf::Reader reader(a.path);
  Record r;
  for (const xtf::XtfChanInfo& c : reader.chan_info())
    if (c.TypeOfChannel == static_cast<std::uint8_t>(xtf::ChannelType::kPort)) {
      r.format_max = format_max(c);
      r.beam_deg = c.HorizBeamAngle;
      break;
    }
  const bool lat_lon = reader.file_header().NavUnits == 3;
  std::optional<sonarsynth::GeoFrame> frame;
  std::vector<rs::Ping> all;
  xtf::Packet packet;
  while (reader.next(packet)) {
    if (packet.kind != xtf::PacketKind::kPing) continue;
    const std::size_t index = r.sonar_pings++;
    if (index < a.first_ping || (a.end_ping > 0 && index >= a.end_ping)) continue;
    const sonarsynth::SonarPing& s = packet.ping.sonar;
    rs::Ping p;
    p.port = s.port;
    p.starboard = s.starboard;
    p.altitude_m = s.altitude_m;
    p.slant_range_m = s.slant_range_m;
    if (lat_lon && packet.ping.nav_valid) {
      if (!frame) frame = sonarsynth::GeoFrame::around(s.sensor_position);
      const auto xy = frame->local_from_geodetic(s.sensor_position);
      p.x_m = xy.x();
      p.y_m = xy.y();
      p.position_valid = true;
    }
    all.push_back(std::move(p));
  }
  // Keep the most common layout (samples per side, slant range), in file order.
  std::map<std::tuple<std::size_t, std::size_t, float>, std::size_t> count;
  for (const rs::Ping& p : all)
    ++count[{p.port.size(), p.starboard.size(), static_cast<float>(p.slant_range_m)}];
  if (count.empty())
    throw InputError("realism: " + a.path + " has no sonar pings" +
                     (a.first_ping > 0 || a.end_ping > 0 ? " in the --pings range" : ""));
  const auto best = std::max_element(count.begin(), count.end(), [](auto& x, auto& y) {
                      return x.second < y.second;
                    })->first;
  if (std::get<0>(best) == 0 || std::get<0>(best) != std::get<1>(best))
    throw InputError("realism: " + a.path + ": the most common ping layout has " +
                     std::to_string(std::get<0>(best)) + " port and " +
                     std::to_string(std::get<1>(best)) +
                     " starboard samples (need both sides, the same count)");
  for (rs::Ping& p : all)
    if (std::make_tuple(p.port.size(), p.starboard.size(), static_cast<float>(p.slant_range_m)) ==
        best)
      r.pings.push_back(std::move(p));
  if (a.beam_deg > 0.0) r.beam_deg = a.beam_deg;
  return r;
}

// One figure per side: port, starboard, pooled.
struct Row {
  std::string key, label, unit;
  double v[3];
};

double pct(std::uint64_t part, std::uint64_t whole) {
  return whole > 0 ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : rs::kNaN;
}

// The rows of measures 1 (seabed texture) and 2 (water column and levels); add(key, label, unit,
// f) adds a row of f over port, starboard and both (rows).
void texture_level_rows(const rs::Report& r, auto& add) {
  // 1. seabed texture
  add("tile_contrast", "1 seabed std/mean, median tile", "",
      [](auto& x) { return x.texture.median_tile_contrast(); });
  add("tile_db_std", "1 seabed std of 10log10, median tile", "dB",
      [](auto& x) { return x.texture.median_tile_db_std(); });
  add("seabed_contrast", "1 seabed std/mean, all seabed", "",
      [](auto& x) { return x.texture.contrast(); });
  add("seabed_db_std", "1 seabed std of 10log10, all seabed", "dB",
      [](auto& x) { return x.texture.db.stddev(); });
  add("tiles", "1 tiles measured", "",
      [](auto& x) { return static_cast<double>(x.texture.tile_contrast.size()); });
  const std::vector<double>& edges = r.pooled.texture.grazing_edges_rad;
  auto class_name = [&](std::size_t c) {
    return std::to_string(std::lround(edges[c] / rs::kDeg)) + "-" +
           std::to_string(std::lround(edges[c + 1] / rs::kDeg));
  };
  for (std::size_t c = 0; c + 1 < edges.size(); ++c)
    add("grazing_" + class_name(c) + "_contrast",
        "1 seabed std/mean, grazing " + class_name(c) + " deg", "", [c](auto& x) {
          const rs::Moments& m = x.texture.grazing_ratio[c];
          return m.n >= 100.0 ? m.stddev() / m.mean() : rs::kNaN;
        });
  for (std::size_t c = 0; c + 1 < edges.size(); ++c)
    add("grazing_" + class_name(c) + "_db_std",
        "1 seabed std of 10log10, grazing " + class_name(c) + " deg", "dB", [c](auto& x) {
          const rs::Moments& m = x.texture.grazing_db[c];
          return m.n >= 100.0 ? m.stddev() : rs::kNaN;
        });
  // 2. water column
  add("water_median_db", "2 water column median level", "dB",
      [](auto& x) { return x.levels.water.median_db(); });
  add("near_median_db", "2 near seabed (1.2-1.5 r0) median level", "dB",
      [](auto& x) { return x.levels.near.median_db(); });
  add("water_minus_near_db", "2 water column - near seabed", "dB",
      [](auto& x) { return x.levels.water.median_db() - x.levels.near.median_db(); });
  for (const auto& [q, name] : {std::pair{0.1, "p10"}, {0.5, "p50"}, {0.9, "p90"}})
    add(std::string("ping_water_minus_near_db_") + name,
        std::string("2 per ping water - near seabed, ") + name, "dB",
        [q](auto& x) { return rs::quantile(x.levels.ping_water_minus_near_db, q); });
  add("zeros_pct", "2 exactly-zero samples, all", "%",
      [](auto& x) { return pct(x.levels.zeros, x.levels.samples); });
  add("water_zeros_pct", "2 exactly-zero samples, water column", "%",
      [](auto& x) { return pct(x.levels.water_zeros, x.levels.water.count()); });
  add("seabed_zeros_pct", "2 exactly-zero samples, seabed", "%",
      [](auto& x) { return pct(x.levels.seabed_zeros, x.levels.seabed.count()); });
  add("seabed_dark_pct", "2 seabed samples below 16", "%",
      [](auto& x) { return pct(x.levels.seabed_dark, x.levels.seabed.count()); });
}

// The rows of measures 3 (shadows), 4 (first return) and 5 (full scale).
void shadow_first_return_rows(const rs::Report& r, auto& add) {
  const double fs_db = rs::level_db(r.max_value);
  // 3. shadows
  add("shadow_pct", "3 shadow samples / seabed samples", "%",
      [](auto& x) { return pct(x.shadows.shadow, x.shadows.seabed); });
  for (const auto& [q, name] : {std::pair{0.25, "p25"}, {0.5, "p50"}})
    add(std::string("shadow_minus_lit_db_") + name,
        std::string("3 shadow - lit seabed at same range, ") + name, "dB",
        [q](auto& x) { return x.shadows.below_lit.quantile_db(q); });
  add("shadow_minus_water_db", "3 shadow - water column (medians)", "dB",
      [](auto& x) { return x.shadows.level.median_db() - x.levels.water.median_db(); });
  // 4. first return
  add("first_return_found_pct", "4 pings with a first return", "%",
      [](auto& x) { return pct(x.first.found, x.first.pings); });
  add("first_return_m", "4 first-return range r0 (median)", "m",
      [](auto& x) { return rs::quantile(x.first.range_m, 0.5); });
  add("first_return_minus_altitude_m", "4 first-return range - altitude (median)", "m",
      [](auto& x) { return rs::quantile(x.first.range_minus_altitude_m, 0.5); });
  add("first_return_over_altitude", "4 first-return range / altitude (median)", "",
      [](auto& x) { return rs::quantile(x.first.range_over_altitude, 0.5); });
  add("rise_12db_m", "4 first return -> -12 dB of near seabed", "m",
      [](auto& x) { return x.first.rise_m(12.0); });
  add("rise_3db_m", "4 first return -> -3 dB of near seabed", "m",
      [](auto& x) { return x.first.rise_m(3.0); });
  add("rise_12db_r0_pct", "4 first return -> -12 dB, in r0", "%",
      [](auto& x) { return 100.0 * x.first.rise_r0(12.0); });
  add("rise_3db_r0_pct", "4 first return -> -3 dB, in r0", "%",
      [](auto& x) { return 100.0 * x.first.rise_r0(3.0); });
  // 5. full scale
  add("seabed_below_full_scale_db", "5 full scale - seabed median", "dB",
      [fs_db](auto& x) { return fs_db - x.levels.seabed.median_db(); });
  add("near_below_full_scale_db", "5 full scale - near seabed median", "dB",
      [fs_db](auto& x) { return fs_db - x.levels.near.median_db(); });
  add("seabed_clipped_pct", "5 seabed samples at full scale", "%",
      [](auto& x) { return pct(x.levels.seabed_clipped, x.levels.seabed.count()); });
  add("near_clipped_pct", "5 near seabed samples at full scale", "%",
      [](auto& x) { return pct(x.levels.near_clipped, x.levels.near.count()); });
  add("lead_below_full_scale_db", "5 full scale - leading samples median", "dB",
      [fs_db](auto& x) { return fs_db - x.levels.lead.median_db(); });
  add("lead_clipped_pct", "5 leading samples at full scale", "%",
      [](auto& x) { return pct(x.levels.lead_clipped, x.levels.lead.count()); });
}

// The rows of measures 6 and 7 (along- and across-track correlation, spectrum).
void correlation_rows(const rs::Report& r, auto& add) {
  // 6. along-track correlation per band
  const std::size_t bands = r.pooled.texture.bands.size();
  auto band_label = [&](std::size_t b, const char* what) {
    const double lo = static_cast<double>(b) * r.pooled.texture.band_m;
    char label[96];
    std::snprintf(label, sizeof label, "6 lag-1 correlation %.1f-%.1f m, %s", lo,
                  lo + r.pooled.texture.band_m, what);
    return std::string(label);
  };
  for (std::size_t b = 0; b < bands; ++b) {
    add("lag1_tile_band_" + std::to_string(b), band_label(b, "median tile"), "",
        [b](auto& x) { return x.texture.median_tile_lag1(b); });
  }
  for (std::size_t b = 0; b < bands; ++b) {
    add("lag1_band_" + std::to_string(b), band_label(b, "all seabed"), "",
        [b](auto& x) { return x.texture.bands[b].correlation(); });
  }
  // 7. across-track correlation and spectrum
  const char* places[3] = {"near", "mid", "far"};
  for (std::size_t p = 0; p < 3; ++p)
    add(std::string("across_lag1_") + places[p],
        std::string("7 across-track lag-1, ") + places[p] + " tile, median tile", "",
        [p](auto& x) { return x.texture.median_tile_across_lag1(p); });
  for (std::size_t p = 0; p < 3; ++p)
    add(std::string("across_lag1_all_") + places[p],
        std::string("7 across-track lag-1, ") + places[p] + " tile, all pairs", "",
        [p](auto& x) { return x.texture.across[p].correlation(); });
  for (std::size_t p = 0; p < 3; ++p)
    add(std::string("across_tiles_") + places[p],
        std::string("7 across-track tiles measured, ") + places[p], "",
        [p](auto& x) { return static_cast<double>(x.texture.tile_across_lag1(p).size()); });
  for (std::size_t q = 0; q < 4; ++q)
    add("across_spectrum_q" + std::to_string(q + 1),
        "7 across-track spectrum, quarter " + std::to_string(q + 1) + " / mean", "",
        [q](auto& x) { return x.texture.spectrum_quarter(q); });
  for (std::size_t q = 0; q < 4; ++q)
    add("across_spectrum_tile_q" + std::to_string(q + 1),
        "7 across-track spectrum, quarter " + std::to_string(q + 1) + ", median tile", "",
        [q](auto& x) { return x.texture.median_tile_spectrum_quarter(q); });
  add("across_spectrum_rows", "7 across-track spectrum rows", "",
      [](auto& x) { return static_cast<double>(x.texture.spectrum_rows()); });
}

// The rows of measures 9 (shadow fill), 10 (shadow edge) and 11 (water column statistics).
void shadow_water_rows(auto& add) {
  // 9. shadow fill
  add("shadow_cv", "9 shadow samples std/mean (values)", "",
      [](auto& x) { return x.shadows.cv_shadow(); });
  add("shadow_region_cv_p50", "9 shadow std/mean, median region", "",
      [](auto& x) { return rs::quantile(x.shadows.region_cv, 0.5); });
  for (const auto& [q, name] : {std::pair{0.25, "p25"}, {0.75, "p75"}})
    add(std::string("shadow_region_cv_") + name, std::string("9 shadow std/mean, region ") + name,
        "", [q](auto& x) { return rs::quantile(x.shadows.region_cv, q); });
  add("shadow_regions", "9 shadow regions (>= 50 samples)", "",
      [](auto& x) { return static_cast<double>(x.shadows.region_cv.size()); });
  add("lit_cv", "9 lit seabed std/mean (values)", "", [](auto& x) { return x.shadows.cv_lit(); });
  // 10. shadow edge
  add("shadow_edge_width_m", "10 shadow -> lit edge, 10-90 % width", "m",
      [](auto& x) { return x.shadows.edge_width_m(); });
  add("shadow_edge_transitions", "10 shadow -> lit edges averaged", "",
      [](auto& x) { return static_cast<double>(x.shadows.edge_count()); });
  add("shadow_edge_in_15_25m", "10 edges from 15-25 m only (1) or all ranges (0)", "",
      [](auto& x) { return x.shadows.edge_in_window() ? 1.0 : 0.0; });
  // 11. water column statistics
  add("water_block_cv_p50", "11 water std/mean, 64-ping blocks, median", "",
      [](auto& x) { return rs::quantile(x.levels.water_block_cv, 0.5); });
  for (const auto& [q, name] : {std::pair{0.25, "p25"}, {0.5, "p50"}, {0.75, "p75"}})
    add(std::string("water_ping_cv_") + name,
        std::string("11 water std/mean, single ping, ") + name, "",
        [q](auto& x) { return rs::quantile(x.levels.water_ping_cv, q); });
  add("water_skewness", "11 water skewness, pooled", "",
      [](auto& x) { return x.levels.water_stats.skewness(); });
  add("water_block_skewness_p50", "11 water skewness, 64-ping blocks, median", "",
      [](auto& x) { return rs::quantile(x.levels.water_block_skewness, 0.5); });
  add("water_min", "11 water lowest value", "count", [](auto& x) { return x.levels.water_min; });
  add("water_trend_db", "11 water median level, last - first third", "dB",
      [](auto& x) { return x.levels.water_trend_db(); });
}

// The rows of measures 12 (first return profile) to 15 (levels of all samples).
void profile_level_rows(const rs::Report& r, auto& add) {
  // 12. first return profile
  const std::vector<double>& offsets = r.pooled.first.profile_offsets_m;
  for (bool from_altitude : {false, true})
    for (std::size_t j = 0; j < offsets.size(); ++j) {
      char key[64], label[96];
      std::snprintf(key, sizeof key, "first_profile_%s_%03.0fcm_db",
                    from_altitude ? "altitude" : "r0", 100.0 * offsets[j]);
      std::snprintf(label, sizeof label, "12 level at %s + %.2f m - near seabed",
                    from_altitude ? "altitude" : "r0", offsets[j]);
      add(key, label, "dB",
          [j, from_altitude](auto& x) { return x.first.profile_db(j, from_altitude); });
    }
  add("first_profile_max_drop_db", "12 median profile r0..+0.5 m, largest drop", "dB",
      [](auto& x) { return x.first.profile_max_drop_db(); });
  add("first_profile_monotone", "12 ... monotone within 1 dB (1 yes, 0 no)", "", [](auto& x) {
    const double d = x.first.profile_max_drop_db();
    return std::isnan(d) ? rs::kNaN : d <= x.first.monotone_tol_db ? 1.0 : 0.0;
  });
  // 13. far range vs near range
  add("far_minus_near_db", "13 level [0.9, 0.97) R - [1.4, 1.6) r0", "dB",
      [](auto& x) { return rs::quantile(x.levels.far_minus_near_db, 0.5); });
  add("altitude_over_range", "13 altitude / R (median)", "",
      [](auto& x) { return rs::quantile(x.levels.altitude_over_range, 0.5); });
  // 14. near-range clipping
  add("first_2m_clipped_pct", "14 samples [r0, r0 + 2 m) at full scale", "%",
      [](auto& x) { return pct(x.levels.first_metres_clipped, x.levels.first_metres); });
  // 15. levels of all samples
  for (const auto& [q, name] : {std::pair{0.01, "p01"}, {0.5, "p50"}, {0.99, "p99"}})
    add(std::string("level_") + name + "_db", std::string("15 level of all samples, ") + name, "dB",
        [q](auto& x) { return x.levels.all.quantile_db(q); });
}

std::vector<Row> rows(const rs::Report& r) {
  std::vector<Row> out;
  const rs::SideReport* s[3] = {&r.port, &r.starboard, &r.pooled};
  auto add = [&](std::string key, std::string label, std::string unit, auto f) {
    Row row{std::move(key), std::move(label), std::move(unit), {}};
    for (int i = 0; i < 3; ++i) row.v[i] = f(*s[i]);
    out.push_back(std::move(row));
  };
  texture_level_rows(r, add);
  shadow_first_return_rows(r, add);
  correlation_rows(r, add);
  shadow_water_rows(add);
  profile_level_rows(r, add);
  return out;
}

std::string fmt(double v) {
  if (std::isnan(v)) return "-";
  if (std::isinf(v)) return v < 0 ? "-inf" : "inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, std::abs(v) >= 100.0 ? "%.1f" : "%.3f", v);
  return buf;
}

nlohmann::json num(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args args = parse_args(argc, argv);
    const Record rec = read_record(args);
    const rs::Report r = rs::measure(rec.pings);
    const std::vector<Row> table = rows(r);
    std::vector<double> altitude;
    for (const rs::Ping& p : rec.pings)
      if (p.altitude_m > 0.0) altitude.push_back(p.altitude_m);
    const double altitude_m = rs::quantile(altitude, 0.5);
    const double beam_rad = sonarsynth::rad_from_deg(rec.beam_deg);
    const std::size_t bands = r.pooled.texture.bands.size();
    auto predicted = [&](std::size_t b) {
      const double mid = (static_cast<double>(b) + 0.5) * r.pooled.texture.band_m;
      const double footprint = mid * beam_rad;
      if (!(footprint > 0.0) || !std::isfinite(r.ping_spacing_m)) return rs::kNaN;
      const double q = r.ping_spacing_m / footprint;
      return std::max(0.0, 1.0 - q * q);
    };
    if (args.json) {
      nlohmann::json j;
      j["file"] = args.path;
      j["sonar_pings"] = rec.sonar_pings;
      j["pings_measured"] = r.pings;
      j["samples_per_side"] = r.samples;
      j["slant_range_m"] = r.slant_range_m;
      j["full_scale"] = num(r.max_value);
      j["format_max"] = num(rec.format_max);
      j["first_ping"] = args.first_ping;
      j["ping_spacing_m"] = num(r.ping_spacing_m);
      j["median_altitude_m"] = num(altitude_m);
      j["horizontal_beam_deg"] = rec.beam_deg;
      j["altitude_min_m"] = num(r.altitude_min_m);
      j["altitude_median_m"] = num(r.altitude_median_m);
      j["altitude_max_m"] = num(r.altitude_max_m);
      for (const Row& row : table)
        j["figures"][row.key] = {{"port", num(row.v[0])},
                                 {"starboard", num(row.v[1])},
                                 {"pooled", num(row.v[2])},
                                 {"unit", row.unit}};
      for (std::size_t b = 0; b < bands; ++b) j["lag1_predicted"].push_back(num(predicted(b)));
      // Measure 8: the along-track lag-1 of measure 6, median tile, one entry per band.
      for (std::size_t b = 0; b < bands; ++b) {
        const double lo = static_cast<double>(b) * r.pooled.texture.band_m;
        j["lag1_along_track_median_tile"].push_back(
            {{"band_m", {lo, lo + r.pooled.texture.band_m}},
             {"port", num(r.port.texture.median_tile_lag1(b))},
             {"starboard", num(r.starboard.texture.median_tile_lag1(b))},
             {"pooled", num(r.pooled.texture.median_tile_lag1(b))}});
      }
      std::printf("%s\n", j.dump(2).c_str());
      return 0;
    }
    std::printf(
        "%s: %zu of %zu sonar pings (from %zu), %zu samples per side, slant range %.2f m, "
        "median altitude %s m\n",
        args.path.c_str(), r.pings, rec.sonar_pings, args.first_ping, r.samples, r.slant_range_m,
        fmt(altitude_m).c_str());
    std::printf(
        "full scale (largest sample) %s (%.1f dB); format maximum %s; ping spacing %s m; "
        "horizontal beam %s deg\n\n",
        fmt(r.max_value).c_str(), rs::level_db(r.max_value), fmt(rec.format_max).c_str(),
        fmt(r.ping_spacing_m).c_str(), fmt(rec.beam_deg).c_str());
    std::printf("%-52s %5s %10s %10s %10s\n", "figure", "unit", "port", "starboard", "pooled");
    for (const Row& row : table)
      std::printf("%-52s %5s %10s %10s %10s\n", row.label.c_str(), row.unit.c_str(),
                  fmt(row.v[0]).c_str(), fmt(row.v[1]).c_str(), fmt(row.v[2]).c_str());
    std::printf("\nlag-1 prediction 1 - (spacing / (range x beam))^2 at band centres:");
    for (std::size_t b = 0; b < bands; ++b) std::printf(" %s", fmt(predicted(b)).c_str());
    std::printf("\n");
    std::printf("\n8 along-track lag-1 (measure 6), median tile, per band:\n");
    std::printf("%-12s %10s %10s %10s\n", "band (m)", "port", "starboard", "pooled");
    for (std::size_t b = 0; b < bands; ++b) {
      const double lo = static_cast<double>(b) * r.pooled.texture.band_m;
      char band[32];
      std::snprintf(band, sizeof band, "%.1f-%.1f", lo, lo + r.pooled.texture.band_m);
      std::printf("%-12s %10s %10s %10s\n", band, fmt(r.port.texture.median_tile_lag1(b)).c_str(),
                  fmt(r.starboard.texture.median_tile_lag1(b)).c_str(),
                  fmt(r.pooled.texture.median_tile_lag1(b)).c_str());
    }
    std::printf("\n16 header altitude (H > 0): min %s m, median %s m, max %s m\n",
                fmt(r.altitude_min_m).c_str(), fmt(r.altitude_median_m).c_str(),
                fmt(r.altitude_max_m).c_str());
    return 0;
  } catch (const sonarsynth::Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
