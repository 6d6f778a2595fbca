// SPDX-License-Identifier: MIT
// effective.yaml: the simulation file as a run resolved it (docs/scene-format.md).
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "sonarsynth/formats/config/option_table.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"
#include "sonarsynth/formats/config/yaml_fields.hpp"

namespace sonarsynth {

namespace fs = std::filesystem;

namespace {

// The resolved sonar of a run into the `sonar` map of effective.yaml: every declared key of the
// section, the vertical beam and the pulse (the keys of their shape and type).
void write_resolved_sonar(YAML::Node sonar, const SimulationSetup& setup) {
  const auto put = [&setup](YAML::Node n, std::string_view path) {
    const options::Option& o = options::at(path);
    n[std::string(o.key)] = options::emit(o, setup);
  };
  for (const options::Option* o : options::in_section("sonar")) put(sonar, o->path());
  YAML::Node beam(YAML::NodeType::Map);
  put(beam, "sonar.vertical_beam.shape");
  const VerticalBeamPattern& v = setup.config.sonar.vertical_beam;
  switch (v.shape) {
    case VerticalBeamShape::uniform:
      break;
    case VerticalBeamShape::gaussian:
      put(beam, "sonar.vertical_beam.width_deg");
      break;
    case VerticalBeamShape::paper_sine_pair:
      put(beam, "sonar.vertical_beam.upper_half_width_deg");
      put(beam, "sonar.vertical_beam.lower_half_width_deg");
      break;
    case VerticalBeamShape::sinc:
      put(beam, "sonar.vertical_beam.height_over_wavelength");
      break;
    case VerticalBeamShape::table:
      for (std::size_t i = 0; i < v.table_off_axis_rad.size(); ++i) {
        beam["off_axis_deg"].push_back(deg_from_rad(v.table_off_axis_rad[i]));
        beam["gain_db"].push_back(v.table_gain_db[i]);
      }
      break;
  }
  sonar["vertical_beam"] = beam;
  YAML::Node pulse(YAML::NodeType::Map);
  put(pulse, "sonar.pulse.type");
  put(pulse, setup.config.sonar.pulse == SonarConfig::Pulse::kCw ? "sonar.pulse.length_us"
                                                                 : "sonar.pulse.bandwidth_khz");
  sonar["pulse"] = pulse;
}

}  // namespace

void write_effective_config(const std::string& scene_path, const SimulationOverrides& overrides,
                            const SimulationSetup& setup, const Simulator& sim,
                            const std::filesystem::path& out_path,
                            const std::vector<std::string>& product_flags, bool absolute_files) {
  YAML::Node root = yaml::load_file(scene_path);
  // `derived` is ignored on input and replaced below: dropped before any traversal, so that
  // aliases nested in it (a "billion laughs" document) cost nothing.
  root.remove("derived");
  // Relative `file:` entries are made absolute so the copy works from anywhere.
  const fs::path base = fs::absolute(fs::path(scene_path)).parent_path();
  std::function<void(YAML::Node)> absolutize = [&](YAML::Node n) {
    if (n.IsMap()) {
      for (auto kv : n) {
        // Keys are not all checked (e.g. under `description`): compare only plain ones.
        if (kv.first.IsScalar() && kv.first.Scalar() == "file" && kv.second.IsScalar()) {
          const fs::path f(kv.second.Scalar());
          if (!f.is_absolute()) kv.second = (base / f).lexically_normal().string();
        } else {
          absolutize(kv.second);
        }
      }
    } else if (n.IsSequence()) {
      for (auto e : n) absolutize(e);
    }
  };
  if (absolute_files) absolutize(root);
  // A sonar preset stays named, with the values it resolved to beside it: they win over it when
  // the file is read again, so the run is reproduced whatever the preset later becomes.
  if (root["sonar"].IsMap() && root["sonar"]["preset"].IsDefined()) {
    write_resolved_sonar(root["sonar"], setup);
  }
  // The overridden options, from the declarations (formats/config/option_table.cpp); the seed
  // always (a run without one draws it).
  for (const options::Option& o : options::all()) {
    if (!o.flag || (o.kind != options::Kind::seed && !o.flag->given(overrides))) continue;
    YAML::Node n = root;
    std::string_view section = o.section;
    while (!section.empty()) {
      const std::size_t dot = section.find('.');
      n.reset(n[std::string(section.substr(0, dot))]);
      section = dot == std::string_view::npos ? std::string_view{} : section.substr(dot + 1);
    }
    n[std::string(o.key)] = options::emit(o, setup);
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
    if (at.object_planes > at.planes) {
      // The count over the range window of objects and their shadows (docs/physics.md §1.3).
      d["along_track_object_planes"] = at.object_planes;
      d["along_track_object_estimated_error_db"] = at.object_estimated_error_db;
    }
  }
  root["derived"] = d;
  YAML::Emitter e;
  e << root;
  std::ofstream os(out_path);
  os << "# Effective configuration of a sonarsynth run: `sonarsynth simulate` on this file\n"
        "# reproduces the run exactly (same seed, same settings).\n";
  if (!product_flags.empty()) {
    os << "# The products were made with these options; give them again for the same files:\n"
          "# product options:";
    for (const std::string& f : product_flags) os << " " << f;
    os << "\n";
  }
  os << e.c_str() << "\n";
  if (!os) throw FormatError(out_path.string() + ": cannot write");
}

}  // namespace sonarsynth
