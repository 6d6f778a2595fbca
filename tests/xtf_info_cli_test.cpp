// SPDX-License-Identifier: MIT
// `sonarsynth info`: text and --json output for the real Marine Sonic file, and a non-zero exit
// with a clear message for files that are not XTF.
#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_test_util.hpp"
#include "xtf_test_util.hpp"

namespace {

namespace fs = std::filesystem;
const fs::path kData = fs::path(SONARSYNTH_TEST_DATA_DIR);

struct CliRun {
  int exit_code = -1;
  std::string output;  // stdout + stderr
};

CliRun run_cli(const std::string& args) {
  const sonarsynth::test::CliResult r = sonarsynth::test::run_cli(args, fs::temp_directory_path());
  return {r.exit_code, r.out + r.err};
}

TEST(XtfInfoCli, TextReportsTheFiguresOfTheRealFile) {
  const CliRun r = run_cli("info '" + (kData / "xtf" / "scotsman-iver2.xtf").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* want :
       {"NavUnits: 3", "SONAR (0): 461", "Sonar pings: 461", "samples 1024 .. 1024",
        "2013-09-10T21:13:08.000000Z", "2013-09-10T21:14:00.230000Z", "X -68.828337 .. -68.827935",
        "Y 48.445450 .. 48.445863", "zero_navigation: 1"}) {
    EXPECT_NE(r.output.find(want), std::string::npos) << "missing '" << want << "' in\n"
                                                      << r.output;
  }
}

// The JSON parses (nlohmann) and its fields are what tests/data/README.md says the real file
// holds (figures that five independent readers agree on).
TEST(XtfInfoCli, JsonReportsTheFiguresOfTheRealFile) {
  const sonarsynth::test::CliResult r = sonarsynth::test::run_cli(
      "info --json '" + (kData / "xtf" / "scotsman-iver2.xtf").string() + "'",
      fs::temp_directory_path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(r.out)) << r.out;
  EXPECT_EQ(j["size_bytes"], 2066304);
  EXPECT_EQ(j["header"]["NavUnits"], 3);
  EXPECT_EQ(j["header"]["NumberOfSonarChannels"], 2);
  EXPECT_EQ(j["pings"], 461);
  ASSERT_EQ(j["packet_counts"].size(), 1u);  // no other packet types
  EXPECT_EQ(j["packet_counts"]["0"]["name"], "SONAR");
  EXPECT_EQ(j["packet_counts"]["0"]["count"], 461);
  EXPECT_EQ(j["time"]["first"], "2013-09-10T21:13:08.000000Z");
  EXPECT_EQ(j["time"]["last"], "2013-09-10T21:14:00.230000Z");
  EXPECT_NEAR(j["time"]["duration_s"].get<double>(), 52.23, 1e-6);
  EXPECT_EQ(j["navigation"]["units"], "degrees");
  EXPECT_NEAR(j["navigation"]["x"]["min"].get<double>(), -68.82834, 1e-5);
  EXPECT_NEAR(j["navigation"]["x"]["max"].get<double>(), -68.82794, 1e-5);
  EXPECT_NEAR(j["navigation"]["y"]["min"].get<double>(), 48.44545, 1e-5);
  EXPECT_NEAR(j["navigation"]["y"]["max"].get<double>(), 48.44586, 1e-5);
  EXPECT_EQ(j["navigation"]["pings_without_position"], 1);  // ping 0's all-zero navigation
  EXPECT_EQ(j["anomaly_counts"]["zero_navigation"], 1);
  EXPECT_EQ(j["ping_attitude"]["SoundVelocity"]["min"], 750.0);
  EXPECT_EQ(j["ping_attitude"]["SoundVelocity"]["max"], 750.0);
  const std::vector<std::string> types = {"PORT", "STBD"};
  ASSERT_EQ(j["channels"].size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    const nlohmann::json& c = j["channels"][k];
    EXPECT_EQ(c["type"], types[k]) << k;
    EXPECT_EQ(c["pings"], 461) << k;
    EXPECT_EQ(c["samples"]["min"], 1024) << k;
    EXPECT_EQ(c["samples"]["max"], 1024) << k;
    EXPECT_NEAR(c["slant_range_m"]["max"].get<double>(), 30.0, 0.5) << k;
    const nlohmann::json& ci = j["chan_info"][k];
    EXPECT_EQ(ci["BytesPerSample"], 2) << k;
    EXPECT_EQ(ci["SampleFormat"], 3) << k;
    EXPECT_EQ(ci["UniPolar"], 1) << k;
  }
}

// Strings from the file are JSON strings whatever their bytes: the golden file's note, and a
// note with a quote, a backslash and a non-ASCII byte (kept as the character of that code).
TEST(XtfInfoCli, JsonStringsFromTheFileAreEscaped) {
  auto b = sonarsynth::xtf::test::read_bytes(kData / "xtf" / "golden-tiny.xtf");
  const fs::path dir = sonarsynth::xtf::test::temp_dir("info_json_strings");
  const auto info = [&](const fs::path& p) {
    const sonarsynth::test::CliResult r =
        sonarsynth::test::run_cli("info --json '" + p.string() + "'", dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out);
  };
  const nlohmann::json golden = info(kData / "xtf" / "golden-tiny.xtf");
  EXPECT_EQ(golden["header"]["NoteString"], "sonarsynth golden test file");
  EXPECT_EQ(golden["pings"], 2);
  EXPECT_EQ(golden["size_bytes"], 2304);
  // NoteString: 64 bytes at offset 36 of the file header (docs/xtf.md §1.1).
  const std::string note = "a \"q\" \\ \xE9";
  std::fill(b.begin() + 36, b.begin() + 36 + 64, std::uint8_t{0});
  std::copy(note.begin(), note.end(), b.begin() + 36);
  sonarsynth::xtf::test::write_bytes(dir / "note.xtf", b);
  const nlohmann::json j = info(dir / "note.xtf");
  EXPECT_EQ(j["header"]["NoteString"], "a \"q\" \\ \u00e9");
  fs::remove_all(dir);
}

TEST(XtfInfoCli, NotAnXtfFileFailsWithAClearMessage) {
  const fs::path dir = sonarsynth::xtf::test::temp_dir("info_cli");
  sonarsynth::xtf::test::write_bytes(dir / "text.xtf", std::vector<std::uint8_t>(2000, 'x'));
  sonarsynth::xtf::test::write_bytes(dir / "short.xtf", std::vector<std::uint8_t>(100, 0x7B));
  const CliRun r = run_cli("info '" + (dir / "text.xtf").string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("FileFormat = 0x78"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("not an XTF file"), std::string::npos) << r.output;
  const CliRun s = run_cli("info --json '" + (dir / "short.xtf").string() + "'");
  EXPECT_EQ(s.exit_code, 1) << s.output;
  EXPECT_NE(s.output.find("fewer than the 1024-byte XTF file header"), std::string::npos)
      << s.output;
  fs::remove_all(dir);
  const CliRun missing = run_cli("info /nonexistent/file.xtf");
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_NE(missing.output.find("/nonexistent/file.xtf"), std::string::npos) << missing.output;
  const CliRun usage = run_cli("info");
  EXPECT_EQ(usage.exit_code, 2) << usage.output;
}

// A ping whose Year is 65535 has no valid time: it is reported as such, and never printed as a
// wrapped year ("-001").
TEST(XtfInfoCli, YearBeyond9999IsAnInvalidTimeNotAWrappedYear) {
  const fs::path dir = sonarsynth::xtf::test::temp_dir("info_year");
  auto b = sonarsynth::xtf::test::read_bytes(kData / "xtf" / "golden-tiny.xtf");
  ASSERT_EQ(b.size(), 2304u);
  ASSERT_EQ(b[1856 + 14] | (b[1856 + 15] << 8), 2013);  // ping 1's Year
  b[1856 + 14] = 0xFF;
  b[1856 + 15] = 0xFF;
  sonarsynth::xtf::test::write_bytes(dir / "y.xtf", b);
  for (const char* flag : {"", "--json "}) {
    const CliRun r = run_cli(std::string("info ") + flag + "'" + (dir / "y.xtf").string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("invalid time 65535-9-10"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("2013-09-10T21:13:08.000000Z"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("-001"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("65535-"), r.output.find("invalid time 65535-") + 13) << r.output;
  }
  fs::remove_all(dir);
}

}  // namespace
