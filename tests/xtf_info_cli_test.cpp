// SPDX-License-Identifier: MIT
// `sonarsynth info`: text and --json output for the real Marine Sonic file, and a non-zero exit
// with a clear message for files that are not XTF.
#include <gtest/gtest.h>

#include <string>

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

TEST(XtfInfoCli, JsonReportsTheFiguresOfTheRealFile) {
  const CliRun r = run_cli("info --json '" + (kData / "xtf" / "scotsman-iver2.xtf").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.front(), '{');
  for (const char* want :
       {"\"pings\": 461", "\"NavUnits\": 3", "\"0\": {\"name\": \"SONAR\", \"count\": 461}",
        "\"first\": \"2013-09-10T21:13:08.000000Z\"", "\"zero_navigation\": 1",
        "\"samples\": {\"min\": 1024, \"max\": 1024}"}) {
    EXPECT_NE(r.output.find(want), std::string::npos) << "missing '" << want << "' in\n"
                                                      << r.output;
  }
  // Braces and brackets balance (outside strings): a cheap structural check of the JSON.
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < r.output.size(); ++i) {
    const char c = r.output[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '{' || c == '[') {
      ++depth;
    } else if (c == '}' || c == ']') {
      --depth;
      ASSERT_GE(depth, 0);
    }
  }
  EXPECT_EQ(depth, 0);
  EXPECT_FALSE(in_string);
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
