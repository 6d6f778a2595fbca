// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/simulation_file.hpp"

#include <ogrsf_frmts.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/gdal_util.hpp"
#include "sonarsynth/formats/scene_file.hpp"
#include "yaml_fields.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;
using yaml::Fields;

Eigen::Vector2d position(const Scene& scene, const Eigen::Vector2d& centre, const Fields& p) {
  p.only({"lat_deg", "lon_deg", "east_m", "north_m"});
  if (p.has("lat_deg") || p.has("lon_deg")) {
    const double lat = p.number_in("lat_deg", 0.0, -90.0, 90.0);
    const double lon = p.number_in("lon_deg", 0.0, -180.0, 360.0);
    return scene.frame.local_from_geodetic({rad_from_deg(lat), rad_from_deg(lon), 0.0});
  }
  return centre + Eigen::Vector2d(p.number("east_m"), p.number("north_m"));
}

VerticalBeamPattern parse_beam(const Fields& b) {
  VerticalBeamPattern v;
  const std::string shape = b.text("shape", "gaussian");
  if (shape == "uniform") {
    b.only({"shape"});
    v.shape = VerticalBeamShape::uniform;
  } else if (shape == "gaussian") {
    b.only({"shape", "width_deg"});
    v.shape = VerticalBeamShape::gaussian;
    v.width_3db_rad = rad_from_deg(b.number_in("width_deg", 50.0, 0.0, 180.0, true));
  } else if (shape == "paper") {
    b.only({"shape", "upper_half_width_deg", "lower_half_width_deg"});
    v.shape = VerticalBeamShape::paper_sine_pair;
    v.upper_half_width_rad =
        rad_from_deg(b.number_in("upper_half_width_deg", 25.0, 0.0, 180.0, true));
    v.lower_half_width_rad =
        rad_from_deg(b.number_in("lower_half_width_deg", 25.0, 0.0, 180.0, true));
  } else if (shape == "sinc") {
    b.only({"shape", "height_over_wavelength"});
    v.shape = VerticalBeamShape::sinc;
    v.height_over_wavelength = b.number_in("height_over_wavelength", 1.0, 0.0, 1e4, true);
  } else if (shape == "table") {
    b.only({"shape", "off_axis_deg", "gain_db"});
    v.shape = VerticalBeamShape::table;
    const YAML::Node a = b.node()["off_axis_deg"], g = b.node()["gain_db"];
    if (!a.IsSequence() || !g.IsSequence() || a.size() != g.size() || a.size() < 2) {
      b.fail("off_axis_deg", "off_axis_deg and gain_db must be lists of equal length >= 2");
    }
    for (std::size_t i = 0; i < a.size(); ++i) {
      v.table_off_axis_rad.push_back(rad_from_deg(a[i].as<double>()));
      v.table_gain_db.push_back(g[i].as<double>());
    }
  } else {
    b.fail_value("shape", "one of gaussian, paper, sinc, table, uniform");
  }
  try {
    v.validate();
  } catch (const InputError& e) {
    b.fail("", e.what());
  }
  return v;
}

template <class F>
void wrap(const Fields& f, F&& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    f.fail("", e.what());
  }
}

}  // namespace

UtcTime parse_utc(const std::string& text, const std::string& what) {
  int y = 0, mo = 0, d = 0, h = 0, mi = 0;
  double s = 0;
  char z = 0;
  if (std::sscanf(text.c_str(), "%d-%d-%dT%d:%d:%lf%c", &y, &mo, &d, &h, &mi, &s, &z) != 7 ||
      z != 'Z' || mo < 1 || mo > 12 || d < 1 || d > 31 || h < 0 || h > 23 || mi < 0 || mi > 59 ||
      !(s >= 0 && s < 60) || y < 1970 || y > 2100) {
    throw InputError(what + " = '" + text +
                     "'. Violated constraint: UTC time YYYY-MM-DDTHH:MM:SSZ, years 1970-2100");
  }
  const std::chrono::year_month_day ymd{std::chrono::year(y),
                                        std::chrono::month(static_cast<unsigned>(mo)),
                                        std::chrono::day(static_cast<unsigned>(d))};
  if (!ymd.ok()) throw InputError(what + " = '" + text + "': no such date");
  return std::chrono::sys_days(ymd) + std::chrono::hours(h) + std::chrono::minutes(mi) +
         std::chrono::microseconds(std::llround(s * 1e6));
}

std::string format_utc(UtcTime t) {
  const auto days = std::chrono::floor<std::chrono::days>(t);
  const std::chrono::year_month_day ymd{days};
  const auto us = (t - days).count();
  char buf[64];
  std::snprintf(buf, sizeof buf, "%04d-%02u-%02uT%02lld:%02lld:%09.6fZ",
                static_cast<int>(ymd.year()), static_cast<unsigned>(ymd.month()),
                static_cast<unsigned>(ymd.day()), static_cast<long long>(us / 3600000000LL),
                static_cast<long long>(us / 60000000LL % 60),
                static_cast<double>(us % 60000000LL) / 1e6);
  return buf;
}

Survey SimulationSetup::make_survey() const {
  return Survey(lines, vehicle, config.sonar.effective_ping_period_s(), start_time, config.seed);
}

namespace {

// The simulation of the YAML document `doc` over the scene `loaded`; `path` names it in messages.
SimulationSetup build_simulation(Scene loaded, const YAML::Node& doc, const std::string& path,
                                 const fs::path& base_dir, const SimulationOverrides& overrides) {
  SimulationSetup setup{std::move(loaded), {}, {}, {}, {}, "u16", 10.0};
  const Fields top(doc, path, "");
  Scene& scene = setup.scene;
  SimulationConfig& cfg = setup.config;
  const Eigen::Vector4d bb = scene.bathymetry.bounds();
  const Eigen::Vector2d centre(0.5 * (bb[0] + bb[2]), 0.5 * (bb[1] + bb[3]));
  cfg.seed = overrides.seed.value_or(top.seed("seed", 1));

  // Sonar.
  SonarConfig& s = cfg.sonar;
  if (top.has("sonar")) {
    const Fields f = top.child("sonar");
    f.only({"frequency_khz", "range_m", "samples", "sound_speed_m_s", "tilt_deg", "vertical_beam",
            "horizontal_beam_deg", "pulse", "ping_period_s"});
    s.frequency_hz = 1e3 * f.number_in("frequency_khz", s.frequency_hz / 1e3, 0.0, 1e5, true);
    s.max_range_m = f.number_in("range_m", s.max_range_m, 0.0, 1e5, true);
    s.samples_per_channel = static_cast<std::size_t>(f.number_in("samples", 4096, 1, 65535));
    s.sound_speed_m_s = f.number_in("sound_speed_m_s", s.sound_speed_m_s, 1300, 1700);
    s.tilt_rad = rad_from_deg(f.number_in("tilt_deg", 20.0, -90.0, 90.0));
    if (f.has("vertical_beam")) s.vertical_beam = parse_beam(f.child("vertical_beam"));
    s.horizontal_beam_width_rad =
        rad_from_deg(f.number_in("horizontal_beam_deg", 1.0, 0.0, 89.0, true));
    if (f.has("pulse")) {
      const Fields p = f.child("pulse");
      const std::string type = p.text("type", "cw");
      if (type == "cw") {
        p.only({"type", "length_us"});
        s.pulse = SonarConfig::Pulse::kCw;
        s.pulse_length_s = 1e-6 * p.number_in("length_us", 0.0, 0.0, 1e6);
      } else if (type == "chirp") {
        p.only({"type", "bandwidth_khz"});
        s.pulse = SonarConfig::Pulse::kChirp;
        s.bandwidth_hz = 1e3 * p.number_in("bandwidth_khz", 0.0, 0.0, 1e5, true);
      } else {
        p.fail_value("type", "cw or chirp");
      }
    }
    s.ping_period_s = f.number_in("ping_period_s", 0.0, 0.0, 1e3);
  }
  if (overrides.range_m) s.max_range_m = *overrides.range_m;
  if (overrides.samples) s.samples_per_channel = *overrides.samples;

  // Render: physics switches and quality.
  if (top.has("render")) {
    const Fields f = top.child("render");
    f.only({"backscatter", "shadows", "spreading", "beam_pattern", "absorption", "water",
            "calibration_k", "quality"});
    const std::string bs = f.text("backscatter", "paper");
    if (bs == "paper") {
      cfg.physics.backscatter = BackscatterModel::paper;
    } else if (bs == "lambert") {
      cfg.physics.backscatter = BackscatterModel::lambert;
    } else {
      f.fail_value("backscatter", "paper or lambert");
    }
    cfg.physics.shadows = f.boolean("shadows", true);
    cfg.physics.spreading = f.boolean("spreading", true);
    cfg.physics.beam_pattern = f.boolean("beam_pattern", true);
    cfg.physics.absorption = f.boolean("absorption", true);
    cfg.physics.calibration_k = f.number_in("calibration_k", 1.0, 0.0, 1e30, true);
    if (f.has("water")) {
      const Fields w = f.child("water");
      w.only({"temperature_c", "salinity_psu", "ph", "depth_m"});
      cfg.physics.water.temperature_c = w.number_in("temperature_c", 10.0, -2.0, 40.0);
      cfg.physics.water.salinity_psu = w.number_in("salinity_psu", 35.0, 0.0, 45.0);
      cfg.physics.water.ph = w.number_in("ph", 8.0, 6.0, 9.0);
      cfg.physics.water.depth_m = w.number_in("depth_m", 20.0, 0.0, 12000.0);
    }
    if (f.has("quality")) {
      const Fields q = f.child("quality");
      q.only({"grid_subdivisions", "object_segments", "gauss_points", "along_track_planes",
              "along_track_tolerance_db"});
      cfg.quality.profile.grid_subdivisions =
          static_cast<int>(q.number_in("grid_subdivisions", 1, 1, 64));
      cfg.quality.profile.object_segments =
          static_cast<int>(q.number_in("object_segments", 16, 2, 256));
      cfg.quality.gauss_points = static_cast<int>(q.number_in("gauss_points", 2, 1, 5));
      if (q.has("along_track_planes") && q.text("along_track_planes") != "auto") {
        cfg.quality.along_track_planes =
            static_cast<int>(q.number_in("along_track_planes", 1, 1, 64));
      }
      cfg.quality.along_track_tolerance_db =
          q.number_in("along_track_tolerance_db", 1.0, 0.0, 40.0, true);
    }
  }
  if (overrides.quality) {
    const std::string& q = *overrides.quality;
    if (q == "fast") {
      cfg.quality.gauss_points = 1;
      cfg.quality.profile.object_segments = 8;
      cfg.quality.along_track_planes = 1;
    } else if (q == "high") {
      cfg.quality.profile.grid_subdivisions = 4;
      cfg.quality.gauss_points = 3;
      cfg.quality.along_track_planes = QualityConfig::kAutoPlanes;
      cfg.quality.along_track_tolerance_db = 0.25;
    } else if (q != "default") {
      throw InputError("--quality = '" + q + "'. Violated constraint: fast, default or high");
    }
  }

  // Noise.
  if (top.has("noise")) {
    const Fields f = top.child("noise");
    f.only({"model", "uniform_half_width", "snr_db", "texture", "freeze_cell_m"});
    const std::string m = f.text("model", "speckle");
    if (m == "none") {
      cfg.noise.model = NoiseConfig::Model::kNone;
    } else if (m == "paper") {
      cfg.noise.model = NoiseConfig::Model::kPaper;
    } else if (m == "speckle") {
      cfg.noise.model = NoiseConfig::Model::kSpeckle;
    } else {
      f.fail_value("model", "none, paper or speckle");
    }
    cfg.noise.paper_uniform_half_width = f.number_in("uniform_half_width", 0.3, 0.0, 1.0);
    cfg.noise.snr_at_max_range_db = f.number_in("snr_db", 20.0, -100.0, 200.0);
    cfg.noise.texture = f.boolean("texture", true);
    cfg.noise.freeze_cell_m = f.number_in("freeze_cell_m", 0.0, 0.0, 1e3);
  }

  // Output scaling and format.
  if (top.has("output")) {
    const Fields f = top.child("output");
    f.only({"tvg", "gain_db", "sample_format", "truth"});
    const std::string tvg = f.text("tvg", "spherical");
    if (tvg == "spherical") {
      cfg.output.tvg = TvgLaw::spherical;
    } else if (tvg == "none") {
      cfg.output.tvg = TvgLaw::none;
    } else {
      f.fail_value("tvg", "spherical (30 log R + 2 alpha R) or none");
    }
    if (f.has("gain_db") && f.text("gain_db") != "auto") cfg.output.gain_db = f.number("gain_db");
    setup.sample_format = f.text("sample_format", "u16");
    if (setup.sample_format == "u16") {
      cfg.output.max_value = 32767.0;
    } else if (setup.sample_format == "u8") {
      cfg.output.max_value = 255.0;
    } else if (setup.sample_format == "f32") {
      cfg.output.max_value = 3.0e38;
      cfg.output.round_to_integer = false;
      cfg.output.gain_db =
          f.has("gain_db") && f.text("gain_db") != "auto" ? cfg.output.gain_db : 0.0;
    } else {
      f.fail_value("sample_format", "u16, u8 or f32");
    }
    cfg.truth = f.boolean("truth", true);
  }
  cfg.threads = overrides.threads.value_or(0);

  // Survey.
  const Fields sv = top.child("survey");
  sv.only({"start_time", "speed_m_s", "altitude_m", "depth_m", "layback_m", "lever_arm_m",
           "turn_time_s", "turn_radius_m", "disturbance", "lines"});
  setup.start_time =
      parse_utc(sv.text("start_time", "2026-01-01T00:00:00Z"), path + ": survey.start_time");
  VehicleConfig& v = setup.vehicle;
  v.speed_m_s = sv.number_in("speed_m_s", 2.0, 0.0, 100.0, true);
  if (sv.has("altitude_m") && sv.has("depth_m"))
    sv.fail("", "give altitude_m or depth_m, not both");
  if (sv.has("depth_m")) {
    v.depth_mode = VehicleConfig::DepthMode::kDepth;
    v.depth_m = sv.number_in("depth_m", 0.0, 0.0, 12000.0);
    const auto [lo, hi] = scene.bathymetry.height_range();
    setup.reference_altitude_m = std::max(0.5, -v.depth_m - 0.5 * (lo + hi));
  } else {
    v.altitude_m = sv.number_in("altitude_m", 10.0, 0.0, 12000.0, true);
    setup.reference_altitude_m = v.altitude_m;
  }
  v.layback_m = sv.number_in("layback_m", 0.0, 0.0, 1e4);
  if (sv.has("lever_arm_m")) {
    const auto la = sv.numbers("lever_arm_m", 3);
    v.lever_arm_m = {la[0], la[1], la[2]};
  }
  v.turn_time_s = sv.number("turn_time_s", -1.0);
  v.turn_radius_m = sv.number_in("turn_radius_m", 25.0, 0.0, 1e5);
  if (sv.has("disturbance")) {
    const Fields d = sv.child("disturbance");
    d.only({"roll_deg", "pitch_deg", "yaw_deg", "heave_m", "period_s"});
    v.disturbance.roll_amplitude_rad = rad_from_deg(d.number_in("roll_deg", 0.0, 0.0, 89.0));
    v.disturbance.pitch_amplitude_rad = rad_from_deg(d.number_in("pitch_deg", 0.0, 0.0, 89.0));
    v.disturbance.yaw_amplitude_rad = rad_from_deg(d.number_in("yaw_deg", 0.0, 0.0, 180.0));
    v.disturbance.heave_amplitude_m = d.number_in("heave_m", 0.0, 0.0, 100.0);
    v.disturbance.period_s = d.number_in("period_s", 8.0, 0.0, 1e4, true);
  }
  wrap(sv, [&] { v.validate(); });
  for (const Fields& l : sv.sequence("lines")) {
    if (l.has("file")) {
      l.only({"file", "layer"});
      const std::string vpath = yaml::resolve_path(base_dir, l.text("file"));
      gdal::VectorLayer vl =
          gdal::open_vector_layer(vpath, l.text("layer", ""), scene.frame.epsg(), false, "survey");
      OGRLayer* layer = vl.layer;
      for (auto& feature : *layer) {
        OGRGeometry* g = feature->GetGeometryRef();
        if (!g || wkbFlatten(g->getGeometryType()) != wkbLineString) continue;
        std::unique_ptr<OGRGeometry> gc(g->clone());
        if (gc->transform(vl.to_target.get()) != OGRERR_NONE)
          throw FormatError(vpath + ": cannot transform a line");
        SurveyLine line;
        const int name_idx = feature->GetFieldIndex("name");
        line.name = name_idx >= 0 ? feature->GetFieldAsString(name_idx)
                                  : "line" + std::to_string(setup.lines.size() + 1);
        for (const OGRPoint& pt : *gc->toLineString()) {
          line.waypoints_xy_m.push_back(scene.frame.local_from_projected({pt.getX(), pt.getY()}));
        }
        setup.lines.push_back(std::move(line));
      }
      continue;
    }
    l.only({"name", "waypoints"});
    SurveyLine line;
    line.name = l.text("name", "line" + std::to_string(setup.lines.size() + 1));
    for (const Fields& w : l.sequence("waypoints"))
      line.waypoints_xy_m.push_back(position(scene, centre, w));
    if (line.waypoints_xy_m.size() < 2) l.fail("waypoints", "a line needs at least 2 waypoints");
    setup.lines.push_back(std::move(line));
  }
  if (setup.lines.empty()) sv.fail("lines", "no survey lines");
  // Line names become file names: unique, and made of letters, digits, '-', '_' and '.'.
  std::set<std::string> names;
  for (const SurveyLine& line : setup.lines) {
    const bool safe = !line.name.empty() && line.name[0] != '.' &&
                      std::all_of(line.name.begin(), line.name.end(), [](char ch) {
                        return std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' ||
                               ch == '_' || ch == '.';
                      });
    if (!safe)
      sv.fail("lines",
              "line name '" + line.name + "' must use only letters, digits, '-', '_', '.'");
    if (!names.insert(line.name).second)
      sv.fail("lines", "line name '" + line.name + "' is used twice");
  }
  wrap(top, [&] { cfg.validate(); });
  return setup;
}

}  // namespace

SimulationSetup load_simulation(const std::string& path, const SimulationOverrides& overrides) {
  Scene scene = load_scene(path);
  return yaml::with_file_errors(path, [&] {
    return build_simulation(std::move(scene), yaml::load_file(path), path,
                            fs::path(path).parent_path(), overrides);
  });
}

SimulationSetup load_simulation_from_string(const std::string& yaml_text, const std::string& name,
                                            const std::filesystem::path& base_dir,
                                            const SimulationOverrides& overrides) {
  Scene scene = load_scene_from_string(yaml_text, name, base_dir);
  return yaml::with_file_errors(name, [&] {
    return build_simulation(std::move(scene), yaml::load_string(yaml_text, name), name, base_dir,
                            overrides);
  });
}

void write_effective_config(const std::string& scene_path, const SimulationOverrides& overrides,
                            const SimulationSetup& setup, const Simulator& sim,
                            const std::filesystem::path& out_path) {
  YAML::Node root = yaml::load_file(scene_path);
  // Relative `file:` entries are made absolute so the copy works from anywhere.
  const fs::path base = fs::absolute(fs::path(scene_path)).parent_path();
  std::function<void(YAML::Node)> absolutize = [&](YAML::Node n) {
    if (n.IsMap()) {
      for (auto kv : n) {
        if (kv.first.as<std::string>() == "file" && kv.second.IsScalar()) {
          const fs::path f(kv.second.as<std::string>());
          if (!f.is_absolute()) kv.second = (base / f).lexically_normal().string();
        } else {
          absolutize(kv.second);
        }
      }
    } else if (n.IsSequence()) {
      for (auto e : n) absolutize(e);
    }
  };
  absolutize(root);
  root["seed"] = setup.config.seed;
  if (overrides.range_m) root["sonar"]["range_m"] = *overrides.range_m;
  if (overrides.samples) root["sonar"]["samples"] = *overrides.samples;
  if (overrides.quality) {
    const QualityConfig& q = setup.config.quality;
    YAML::Node qn = root["render"]["quality"];
    qn["grid_subdivisions"] = q.profile.grid_subdivisions;
    qn["object_segments"] = q.profile.object_segments;
    qn["gauss_points"] = q.gauss_points;
    if (q.along_track_planes == QualityConfig::kAutoPlanes) {
      qn["along_track_planes"] = "auto";
    } else {
      qn["along_track_planes"] = q.along_track_planes;
    }
    qn["along_track_tolerance_db"] = q.along_track_tolerance_db;
  }
  YAML::Node d;
  d["note"] = "values derived by sonarsynth for this run (informational; ignored on input)";
  d["epsg"] = setup.scene.frame.epsg();
  d["absorption_db_per_km"] = sim.absorption_db_per_m() * 1000.0;
  d["gain_db"] = sim.gain_db();
  d["thermal_noise_power"] = sim.thermal_noise_power();
  d["ping_period_s"] = setup.config.sonar.effective_ping_period_s();
  d["sample_spacing_m"] = setup.config.sonar.sample_spacing_m();
  d["beta_eff_deg"] = deg_from_rad(setup.config.sonar.beta_eff_rad());
  const AlongTrackChoice& at = sim.along_track();
  d["along_track_planes"] = at.planes;
  if (at.automatic) {
    d["along_track_estimated_error_db"] = at.estimated_error_db;
    d["along_track_pilot_pings"] = at.pilot_pings;
  }
  root["derived"] = d;
  YAML::Emitter e;
  e << root;
  std::ofstream os(out_path);
  os << "# Effective configuration of a sonarsynth run: `sonarsynth simulate` on this file\n"
        "# reproduces the run exactly (same seed, same settings).\n"
     << e.c_str() << "\n";
  if (!os) throw FormatError(out_path.string() + ": cannot write");
}

}  // namespace sonarsynth
