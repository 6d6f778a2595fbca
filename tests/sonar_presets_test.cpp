// SPDX-License-Identifier: MIT
// Sonar presets (docs/sonar-presets.md): each resolves to the values of the doc's table, the
// Sea Scan preset to the headers of the real recording it models, explicit keys win over a
// preset in any order, an unknown name lists the valid ones, and effective.yaml records the
// resolved values and reproduces them.
#include "sonarsynth/sonar_presets.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "cli_test_util.hpp"
#include "simulation_file_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

// One row of the table in docs/sonar-presets.md.
struct DocRow {
  double frequency_khz = 0, range_m = 0, samples = 0, horizontal_deg = 0, vertical_deg = 0,
         tilt_deg = 0, pulse_value = 0;
  std::string pulse;  // "cw" or "chirp"
};

// The table's rows by preset name: the lines "| `name` | ... |" of docs/sonar-presets.md.
std::map<std::string, DocRow> doc_table() {
  std::ifstream in(fs::path(SONARSYNTH_DOCS_DIR) / "sonar-presets.md");
  std::map<std::string, DocRow> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("| `", 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line.substr(1));
    for (std::string cell; std::getline(ss, cell, '|');) cells.push_back(cell);
    if (cells.size() < 8) continue;
    const auto num = [](const std::string& s) { return std::stod(s); };
    DocRow r;
    r.frequency_khz = num(cells[1]);
    r.range_m = num(cells[2]);
    r.samples = num(cells[3]);
    r.horizontal_deg = num(cells[4]);
    r.vertical_deg = num(cells[5]);
    r.tilt_deg = num(cells[6]);
    std::stringstream pulse(cells[7]);  // " cw, length_us 50 "
    std::string key;
    pulse >> r.pulse >> key >> r.pulse_value;
    r.pulse.pop_back();  // the comma
    std::string name = cells[0];
    name = name.substr(name.find('`') + 1);
    rows[name.substr(0, name.find('`'))] = r;
  }
  return rows;
}

TEST(SonarPresets, EachResolvesToTheDocumentedValues) {
  const std::map<std::string, DocRow> doc = doc_table();
  ASSERT_EQ(doc.size(), sonar_presets().size()) << "docs/sonar-presets.md lists other presets";
  for (const SonarPreset& p : sonar_presets()) {
    SCOPED_TRACE(std::string(p.name));
    ASSERT_TRUE(doc.count(std::string(p.name)));
    const DocRow& d = doc.at(std::string(p.name));
    const SonarConfig s = sonar_preset(p.name);
    EXPECT_NO_THROW(s.validate());
    EXPECT_DOUBLE_EQ(s.frequency_hz, d.frequency_khz * 1e3);
    EXPECT_DOUBLE_EQ(s.max_range_m, d.range_m);
    EXPECT_EQ(static_cast<double>(s.samples_per_channel), d.samples);
    EXPECT_NEAR(deg_from_rad(s.horizontal_beam_width_rad), d.horizontal_deg, 1e-12);
    EXPECT_EQ(s.vertical_beam.shape, VerticalBeamShape::gaussian);
    EXPECT_NEAR(deg_from_rad(s.vertical_beam.width_3db_rad), d.vertical_deg, 1e-12);
    EXPECT_NEAR(deg_from_rad(s.tilt_rad), d.tilt_deg, 1e-12);
    if (d.pulse == "cw") {
      EXPECT_EQ(s.pulse, SonarConfig::Pulse::kCw);
      EXPECT_NEAR(s.pulse_length_s, d.pulse_value * 1e-6, 1e-15);
    } else {
      EXPECT_EQ(d.pulse, "chirp");
      EXPECT_EQ(s.pulse, SonarConfig::Pulse::kChirp);
      EXPECT_DOUBLE_EQ(s.bandwidth_hz, d.pulse_value * 1e3);
    }
    // Not set by a preset: SonarConfig's defaults.
    EXPECT_EQ(s.sound_speed_m_s, SonarConfig{}.sound_speed_m_s);
    EXPECT_EQ(s.ping_period_s, 0.0);
    // The sample-count rule of the doc: the fewest power of two (<= 8192) whose spacing is at
    // most the range resolution; the Sea Scan's count is the file's.
    if (p.name != "seascan-hds-600") {
      EXPECT_LE(s.sample_spacing_m(), s.pulse_window_m());
      EXPECT_GT(s.max_range_m / static_cast<double>(s.samples_per_channel / 2), s.pulse_window_m());
      EXPECT_LE(s.samples_per_channel, 8192u);
      EXPECT_EQ(s.samples_per_channel & (s.samples_per_channel - 1), 0u);  // a power of two
    }
  }
}

// The Sea Scan preset against the real Sea Scan HDS recording it models (tests/data/README.md).
TEST(SonarPresets, SeaScanMatchesTheRealRecordingsHeaders) {
  const SonarConfig s = sonar_preset("seascan-hds-600");
  xtf::Reader r(fs::path(SONARSYNTH_TEST_DATA_DIR) / "xtf" / "scotsman-iver2.xtf");
  for (const xtf::XtfChanInfo& c : r.chan_info()) EXPECT_EQ(c.Frequency, 600.0f);
  xtf::Packet p;
  std::size_t channels = 0;
  while (r.next(p)) {
    if (p.kind != xtf::PacketKind::kPing) continue;
    EXPECT_DOUBLE_EQ(2.0 * p.ping.header.SoundVelocity, s.sound_speed_m_s);
    for (std::size_t i = 0; i < p.ping.channel_count; ++i) {
      const xtf::XtfPingChanHeader& h = p.ping.channels[i].header;
      ++channels;
      EXPECT_DOUBLE_EQ(h.Frequency * 1e3, s.frequency_hz);
      EXPECT_EQ(h.NumSamples, s.samples_per_channel);
      EXPECT_NEAR(h.SlantRange, s.max_range_m, 0.001 * s.max_range_m);  // 29.98 m setting 30 m
      // Pings follow each other at the two-way travel time to the range, as the preset's
      // ping period 0 makes them.
      EXPECT_NEAR(h.SecondsPerPing, 2.0 * h.SlantRange / s.sound_speed_m_s, 1e-6);
      EXPECT_EQ(s.ping_period_s, 0.0);
      // The pulse is not in the file (docs/sonar-presets.md: fitted to its seabed's correlation
      // in range): longer than one sample interval of the recording, as that correlation needs.
      EXPECT_GT(s.pulse_length_s, h.TimeDuration / static_cast<double>(h.NumSamples));
    }
  }
  EXPECT_EQ(channels, 2u * 461u);
}

TEST(SonarPresets, UnknownNameListsTheValidOnes) {
  try {
    sonar_preset("klein-3000");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("'klein-3000'"), std::string::npos) << m;
    for (const SonarPreset& p : sonar_presets())
      EXPECT_NE(m.find(std::string(p.name)), std::string::npos) << m;
  }
  EXPECT_EQ(find_sonar_preset("klein-3000"), nullptr);
  EXPECT_EQ(find_sonar_preset("klein-3900-445")->name, "klein-3900-445");
}

const char* kBathy =
    "bathymetry:\n  generate: {centre: {lat_deg: 48.45, lon_deg: -68.83}, size_m: [200, 200], "
    "cell_m: 1, depth_m: 30}\n"
    "render: {quality: {along_track_planes: 1}}\n"
    "survey:\n  altitude_m: 8\n"
    "  lines: [{name: a, waypoints: [{east_m: -20, north_m: 0}, {east_m: 20, north_m: 0}]}]\n";

class SonarPresetFile : public test::ScratchDirTest {
 protected:
  /// A scene file whose `sonar` section is `sonar`.
  std::string scene(const std::string& name, const std::string& sonar) {
    return write(name, std::string(kBathy) + "sonar: " + sonar + "\n").string();
  }
};

TEST_F(SonarPresetFile, ThePresetAloneGivesItsConfiguration) {
  for (const SonarPreset& p : sonar_presets()) {
    const SonarConfig s =
        load_simulation(scene("p.yaml", "{preset: " + std::string(p.name) + "}")).config.sonar;
    EXPECT_EQ(s.frequency_hz, p.sonar.frequency_hz) << p.name;
    EXPECT_EQ(s.max_range_m, p.sonar.max_range_m) << p.name;
    EXPECT_EQ(s.samples_per_channel, p.sonar.samples_per_channel) << p.name;
    EXPECT_EQ(s.tilt_rad, p.sonar.tilt_rad) << p.name;
    EXPECT_EQ(s.horizontal_beam_width_rad, p.sonar.horizontal_beam_width_rad) << p.name;
    EXPECT_EQ(s.vertical_beam.width_3db_rad, p.sonar.vertical_beam.width_3db_rad) << p.name;
    EXPECT_EQ(s.pulse, p.sonar.pulse) << p.name;
    EXPECT_EQ(s.pulse_length_s, p.sonar.pulse_length_s) << p.name;
    EXPECT_EQ(s.bandwidth_hz, p.sonar.bandwidth_hz) << p.name;
  }
}

TEST_F(SonarPresetFile, ExplicitKeysWinInAnyOrder) {
  const SonarConfig k = sonar_preset("klein-3900-445");
  // Keys before and after the preset; a beam of the preset's shape keeps what it does not give.
  const std::string before = scene("before.yaml",
                                   "{range_m: 60, tilt_deg: 12, preset: klein-3900-445, "
                                   "vertical_beam: {width_deg: 30}, pulse: {length_us: 100}}");
  const std::string after = scene("after.yaml",
                                  "{preset: klein-3900-445, range_m: 60, tilt_deg: 12, "
                                  "vertical_beam: {width_deg: 30}, pulse: {length_us: 100}}");
  for (const std::string& path : {before, after}) {
    const SonarConfig s = load_simulation(path).config.sonar;
    EXPECT_EQ(s.max_range_m, 60.0) << path;
    EXPECT_EQ(s.tilt_rad, rad_from_deg(12.0)) << path;
    EXPECT_EQ(s.vertical_beam.shape, VerticalBeamShape::gaussian) << path;
    EXPECT_EQ(s.vertical_beam.width_3db_rad, rad_from_deg(30.0)) << path;
    EXPECT_EQ(s.pulse, SonarConfig::Pulse::kCw) << path;
    EXPECT_DOUBLE_EQ(s.pulse_length_s, 100e-6) << path;
    // The rest is the preset's.
    EXPECT_EQ(s.frequency_hz, 445e3) << path;
    EXPECT_EQ(s.samples_per_channel, k.samples_per_channel) << path;
    EXPECT_EQ(s.horizontal_beam_width_rad, k.horizontal_beam_width_rad) << path;
  }
  // Another shape or pulse type starts from its own defaults; the command line wins over all.
  SimulationOverrides cli;
  cli.range_m = 40.0;
  cli.samples = 2000;
  const SonarConfig s =
      load_simulation(scene("other.yaml",
                            "{preset: edgetech-4200-600, range_m: 70, samples: 4000, "
                            "vertical_beam: {shape: sinc}, pulse: {type: cw, length_us: 20}}"),
                      cli)
          .config.sonar;
  EXPECT_EQ(s.max_range_m, 40.0);
  EXPECT_EQ(s.samples_per_channel, 2000u);
  EXPECT_EQ(s.vertical_beam.shape, VerticalBeamShape::sinc);
  EXPECT_EQ(s.vertical_beam.height_over_wavelength, VerticalBeamPattern{}.height_over_wavelength);
  EXPECT_EQ(s.pulse, SonarConfig::Pulse::kCw);
  EXPECT_DOUBLE_EQ(s.pulse_length_s, 20e-6);
  EXPECT_EQ(s.frequency_hz, 600e3);
}

TEST_F(SonarPresetFile, UnknownPresetNamesTheFileKeyValueAndTheValidNames) {
  const std::string path = scene("bad.yaml", "{preset: klein-3000}");
  try {
    load_simulation(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find("sonar.preset"), std::string::npos) << m;
    EXPECT_NE(m.find("klein-3000"), std::string::npos) << m;
    EXPECT_NE(m.find(sonar_preset_names()), std::string::npos) << m;
  }
}

// effective.yaml keeps the preset name, writes the resolved values beside it, and reading it
// back (with the command-line override now in the file) gives the same sonar.
TEST_F(SonarPresetFile, EffectiveYamlRecordsTheResolvedValues) {
  SimulationOverrides cli;
  cli.samples = 1500;
  for (const SonarPreset& p : sonar_presets()) {
    SCOPED_TRACE(std::string(p.name));
    const std::string path =
        scene("s.yaml", "{preset: " + std::string(p.name) + ", horizontal_beam_deg: 0.7}");
    const SimulationSetup a = load_simulation(path, cli);
    const Simulator sim(a.scene, a.config, a.reference_altitude_m);
    const fs::path eff = dir_ / "effective.yaml";
    write_effective_config(path, cli, a, sim, eff);

    const YAML::Node y = YAML::LoadFile(eff.string())["sonar"];
    EXPECT_EQ(y["preset"].as<std::string>(), p.name);
    EXPECT_DOUBLE_EQ(y["frequency_khz"].as<double>(), p.sonar.frequency_hz / 1e3);
    EXPECT_DOUBLE_EQ(y["range_m"].as<double>(), p.sonar.max_range_m);
    EXPECT_EQ(y["samples"].as<int>(), 1500);
    EXPECT_DOUBLE_EQ(y["tilt_deg"].as<double>(), deg_from_rad(p.sonar.tilt_rad));
    EXPECT_DOUBLE_EQ(y["horizontal_beam_deg"].as<double>(), 0.7);
    EXPECT_EQ(y["vertical_beam"]["shape"].as<std::string>(), "gaussian");
    EXPECT_DOUBLE_EQ(y["vertical_beam"]["width_deg"].as<double>(),
                     deg_from_rad(p.sonar.vertical_beam.width_3db_rad));
    const bool cw = p.sonar.pulse == SonarConfig::Pulse::kCw;
    EXPECT_EQ(y["pulse"]["type"].as<std::string>(), cw ? "cw" : "chirp");
    if (cw) {
      EXPECT_DOUBLE_EQ(y["pulse"]["length_us"].as<double>(), p.sonar.pulse_length_s * 1e6);
    } else {
      EXPECT_DOUBLE_EQ(y["pulse"]["bandwidth_khz"].as<double>(), p.sonar.bandwidth_hz / 1e3);
    }

    const SonarConfig& x = a.config.sonar;
    const SonarConfig b = load_simulation(eff.string()).config.sonar;
    simulation_file_test::expect_same_members(x, b);
  }
}

}  // namespace
}  // namespace sonarsynth
