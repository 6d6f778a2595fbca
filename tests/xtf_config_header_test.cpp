// SPDX-License-Identifier: MIT
// Every XTF header field the configuration determines, written through the survey pipeline
// (Simulator::run -> XtfSurveyWriter with xtf_writer_options) and read back with our reader,
// compared with the configuration of a non-default sonar (docs/xtf.md §1.2, §1.6, §5).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>

#include "cli_test_util.hpp"
#include "simulator_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/survey_writer.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

std::shared_ptr<const Scene> flat_scene() {
  auto scene = std::make_shared<Scene>(
      test::make_scene(-60, -60, 120, 1.0, [](double, double) { return -30.0; }));
  scene->name = "a flat test scene";
  return scene;
}

SimulationConfig odd_sonar() {
  SimulationConfig c;
  c.sonar.frequency_hz = 230e3;
  c.sonar.max_range_m = 35.0;
  c.sonar.samples_per_channel = 500;
  c.sonar.tilt_rad = rad_from_deg(12.0);
  c.sonar.horizontal_beam_width_rad = rad_from_deg(0.7);
  c.sonar.vertical_beam.shape = VerticalBeamShape::paper_sine_pair;
  c.sonar.vertical_beam.upper_half_width_rad = rad_from_deg(21.0);
  c.sonar.vertical_beam.lower_half_width_rad = rad_from_deg(36.0);
  c.seed = 77;
  c.threads = 1;
  return c;
}

// The number that follows `key` in `text`.
double number_after(const std::string& text, const std::string& key) {
  const auto i = text.find(key);
  if (i == std::string::npos) throw std::runtime_error("no '" + key + "' in: " + text);
  return std::stod(text.substr(i + key.size()));
}

struct Written {
  xtf::XtfFileHeader header;
  std::string notes;
  std::vector<xtf::XtfPingChanHeader> channels;
  double gain_db = 0.0, alpha_db_per_m = 0.0;
};

Written write_and_read(const SimulationConfig& cfg, xtf::SampleEncoding enc, const fs::path& dir) {
  const auto scene = flat_scene();
  VehicleConfig v;
  v.speed_m_s = 5.0;
  v.altitude_m = 8.0;
  const Survey survey({SurveyLine{"line", {{-10.0, 0.0}, {10.0, 0.0}}}}, v, 0.5,
                      UtcTime{std::chrono::seconds(1'780'000'000)}, 1);
  const Simulator sim(scene, cfg, v.altitude_m);
  xtf::WriterOptions o = xtf_writer_options(sim, enc, scene->name);
  o.overwrite = true;
  XtfSurveyWriter w(dir, {"line"}, scene->frame, cfg.sonar, o);
  sim.run(survey, w);
  Written out;
  out.gain_db = sim.gain_db();
  out.alpha_db_per_m = sim.absorption_db_per_m();
  xtf::Reader r(dir / "line.xtf");
  out.header = r.file_header();
  xtf::Packet pk;
  while (r.next(pk)) {
    if (pk.kind == xtf::PacketKind::kNotes) out.notes = sonarsynth::to_string(pk.notes.NotesText);
    if (pk.kind == xtf::PacketKind::kPing) {
      for (std::size_t i = 0; i < pk.ping.channel_count; ++i)
        out.channels.push_back(pk.ping.channels[i].header);
    }
  }
  return out;
}

class XtfConfigHeaderTest : public test::ScratchDirTest {
 protected:
};

TEST_F(XtfConfigHeaderTest, EveryFieldFollowsANonDefaultSonarWithTvg) {
  SimulationConfig cfg = odd_sonar();
  cfg.output.tvg = TvgLaw::spherical;
  const Written w = write_and_read(cfg, xtf::SampleEncoding::kUint16, dir_);
  for (int side = 0; side < 2; ++side) {
    const xtf::XtfChanInfo& c = w.header.ChanInfo[static_cast<std::size_t>(side)];
    EXPECT_FLOAT_EQ(c.Frequency, 230.0f);
    EXPECT_FLOAT_EQ(c.TiltAngle, 12.0f);
    EXPECT_FLOAT_EQ(c.HorizBeamAngle, 0.7f);
    // paper pattern b = cos(pi/2 off / w) = 1/2 at 2w/3: 2/3 (21 + 36) = 38 deg.
    EXPECT_NEAR(c.BeamWidth, 38.0f, 1e-4);
    EXPECT_EQ(c.BytesPerSample, 2);
    EXPECT_EQ(c.SampleFormat, 3);
  }
  ASSERT_FALSE(w.channels.empty());
  for (const auto& ch : w.channels) {
    EXPECT_EQ(ch.ProcessingFlags, 4);  // TVG applied
    EXPECT_EQ(ch.Frequency, 230);
  }
  // The note states the law, alpha and the gain; the header's 64 characters hold all three.
  const std::string note_string = sonarsynth::to_string(w.header.NoteString);
  EXPECT_EQ(w.notes.rfind(note_string, 0), 0u) << note_string << " | " << w.notes;
  EXPECT_EQ(note_string.rfind("TVG 30logR+2aR a=", 0), 0u) << note_string;
  EXPECT_NE(note_string.find(" dB;"), std::string::npos) << note_string;
  EXPECT_NEAR(number_after(note_string, "a="), w.alpha_db_per_m, 1e-5 * w.alpha_db_per_m);
  EXPECT_NEAR(number_after(note_string, "gain "), w.gain_db, 1e-8 * std::abs(w.gain_db));
  EXPECT_NE(w.notes.find("scene 'a flat test scene', seed 77"), std::string::npos) << w.notes;
}

TEST_F(XtfConfigHeaderTest, NoTvgGivesNoFlagAndSaysSoWithTheGivenGain) {
  SimulationConfig cfg = odd_sonar();
  cfg.output.tvg = TvgLaw::none;
  cfg.output.gain_db = 123.456789012;
  cfg.output.max_value = 255.0;
  cfg.sonar.vertical_beam.shape = VerticalBeamShape::gaussian;
  cfg.sonar.vertical_beam.width_3db_rad = rad_from_deg(44.0);
  const Written w = write_and_read(cfg, xtf::SampleEncoding::kUint8, dir_);
  for (int side = 0; side < 2; ++side) {
    const xtf::XtfChanInfo& c = w.header.ChanInfo[static_cast<std::size_t>(side)];
    EXPECT_FLOAT_EQ(c.BeamWidth, 44.0f);
    EXPECT_FLOAT_EQ(c.TiltAngle, 12.0f);
    EXPECT_EQ(c.BytesPerSample, 1);
    EXPECT_EQ(c.SampleFormat, 8);
  }
  for (const auto& ch : w.channels) EXPECT_EQ(ch.ProcessingFlags, 0);
  const std::string note_string = sonarsynth::to_string(w.header.NoteString);
  EXPECT_EQ(note_string.rfind("no TVG, gain 123.456789 dB;", 0), 0u) << note_string;
  EXPECT_EQ(w.notes.find("30logR"), std::string::npos) << w.notes;
}

TEST_F(XtfConfigHeaderTest, FloatSamplesAndALongSceneNameKeepTheNoteWithin200Characters) {
  SimulationConfig cfg = odd_sonar();
  cfg.output.max_value = 3.0e38;
  cfg.output.round_to_integer = false;
  const auto scene = flat_scene();
  const Simulator sim(scene, cfg, 8.0);
  const xtf::WriterOptions o =
      xtf_writer_options(sim, xtf::SampleEncoding::kFloat32, std::string(400, 'x'));
  EXPECT_LE(o.note.size(), 200u);
  EXPECT_NE(o.note.find("...', seed 77"), std::string::npos) << o.note;
  EXPECT_EQ(o.sample_encoding, xtf::SampleEncoding::kFloat32);
  EXPECT_NO_THROW(o.validate());
  EXPECT_EQ(xtf_sample_encoding("f32"), xtf::SampleEncoding::kFloat32);
  EXPECT_EQ(xtf_sample_encoding("u8"), xtf::SampleEncoding::kUint8);
  EXPECT_EQ(xtf_sample_encoding("u16"), xtf::SampleEncoding::kUint16);
  EXPECT_THROW(xtf_sample_encoding("s16"), InputError);
}

}  // namespace
}  // namespace sonarsynth
