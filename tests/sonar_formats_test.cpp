// SPDX-License-Identifier: MIT
// The format list (formats/registry/sonar_formats.cpp): every descriptor complete, lookups by name,
// extension and content, the output directory and `info` going through it.
#include "sonarsynth/formats/registry/sonar_formats.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/jsf/format.hpp"
#include "sonarsynth/formats/registry/output_dir.hpp"
#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/rosbag/format.hpp"
#include "sonarsynth/formats/xtf/format.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

const fs::path kData = SONARSYNTH_TEST_DATA_DIR;

TEST(SonarFormats, EveryDescriptorHasWhatItsCapabilitiesPromise) {
  std::set<std::string> names, extensions;
  ASSERT_GE(sonar_formats().size(), 2u);
  for (const SonarFormat* f : sonar_formats()) {
    SCOPED_TRACE(std::string(f->name));
    EXPECT_TRUE(names.insert(std::string(f->name)).second) << "name listed twice";
    EXPECT_FALSE(f->display_name.empty());
    EXPECT_FALSE(f->description.empty());
    ASSERT_FALSE(f->extensions.empty());
    for (std::string_view e : f->extensions) {
      EXPECT_EQ(e.front(), '.');
      EXPECT_TRUE(extensions.insert(std::string(e)).second) << e << " claimed twice";
    }
    if (f->capabilities.read) {
      EXPECT_NE(f->identify, nullptr);
      EXPECT_NE(f->open_reader, nullptr);
      EXPECT_NE(f->info, nullptr);
    }
    if (f->capabilities.simulate) {
      EXPECT_NE(f->create_survey_writer, nullptr);
      EXPECT_NE(f->estimated_bytes, nullptr);
    }
    for (const SonarConversion& c : f->conversions) {
      EXPECT_NE(find_sonar_format(c.from), nullptr) << c.from;
      EXPECT_NE(find_sonar_format(c.to), nullptr) << c.to;
      EXPECT_TRUE(c.from == f->name || c.to == f->name) << "a codec converts to or from itself";
      EXPECT_NE(c.convert, nullptr);
    }
  }
  EXPECT_EQ(sonar_formats()[0], &xtf::sonar_format());  // the default output comes first
  // The first three in this order; later formats append their line.
  EXPECT_TRUE(sonar_format_names().starts_with("xtf, jsf, rosbag")) << sonar_format_names();
}

// A format is named under a capability exactly when it has it, in the list's order; the help
// texts and refusals name formats this way.
TEST(SonarFormats, NamesTheFormatsOfACapability) {
  for (bool SonarFormatCapabilities::*cap :
       {&SonarFormatCapabilities::read, &SonarFormatCapabilities::simulate}) {
    std::string expected;
    for (const SonarFormat* f : sonar_formats()) {
      if (!(f->capabilities.*cap)) continue;
      expected += (expected.empty() ? "" : ", ") + std::string(f->name);
    }
    EXPECT_EQ(sonar_format_names(cap), expected);
  }
  // The codecs of today all read and simulate; an empty capability list would name nothing.
  EXPECT_EQ(sonar_format_names(&SonarFormatCapabilities::read), sonar_format_names());
  EXPECT_TRUE(sonar_format_names(&SonarFormatCapabilities::simulate).starts_with("xtf, jsf"));
}

TEST(SonarFormats, LooksUpByNameAndExtensionInAnyCase) {
  EXPECT_EQ(find_sonar_format("JSF"), &jsf::sonar_format());
  EXPECT_EQ(find_sonar_format("xtf"), &xtf::sonar_format());
  EXPECT_EQ(find_sonar_format("sdf"), nullptr);
  EXPECT_EQ(sonar_format_for_extension("a/b/line.XTF"), &xtf::sonar_format());
  EXPECT_EQ(sonar_format_for_extension("line.jsf"), &jsf::sonar_format());
  EXPECT_EQ(sonar_format_for_extension("line.tif"), nullptr);
  try {
    (void)sonar_format_named("sss", "output.formats");
    FAIL();
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("output.formats = 'sss'"), std::string::npos) << m;
    EXPECT_NE(m.find("one of xtf, jsf, rosbag"), std::string::npos) << m;
  }
}

TEST(SonarFormats, IdentifiesFilesByContentNotByName) {
  const fs::path dir = xtf::test::temp_dir("sonar_formats_identify");
  // The shipped files, each renamed to the other's extension: the content decides.
  fs::copy_file(kData / "xtf" / "golden-tiny.xtf", dir / "really_xtf.jsf");
  fs::copy_file(kData / "jsf" / "tiny-from-xtf.jsf", dir / "really_jsf.xtf");
  EXPECT_EQ(identify_sonar_format(dir / "really_xtf.jsf"), &xtf::sonar_format());
  EXPECT_EQ(identify_sonar_format(dir / "really_jsf.xtf"), &jsf::sonar_format());
  EXPECT_EQ(&SideScanSource::open(dir / "really_jsf.xtf")->format(), &jsf::sonar_format());
  (void)convert_sonar_file(kData / "xtf" / "golden-tiny.xtf", dir / "a.bag", false);
  fs::rename(dir / "a.bag", dir / "really_bag.xtf");
  EXPECT_EQ(identify_sonar_format(dir / "really_bag.xtf"), &rosbag::sonar_format());
  EXPECT_EQ(&SideScanSource::open(dir / "really_bag.xtf")->format(), &rosbag::sonar_format());
  xtf::test::write_bytes(dir / "junk.xtf", {'h', 'e', 'l', 'l', 'o'});
  xtf::test::write_bytes(dir / "one_byte", {0x01});
  xtf::test::write_bytes(dir / "empty", {});
  EXPECT_EQ(identify_sonar_format(dir / "junk.xtf"), nullptr);
  EXPECT_EQ(identify_sonar_format(dir / "one_byte"), nullptr);
  EXPECT_EQ(identify_sonar_format(dir / "empty"), nullptr);
  EXPECT_THROW((void)identify_sonar_format(dir / "missing"), FormatError);
  fs::remove_all(dir);
}

// Old output of every format is recognised as ours (the output directory's product check takes
// the extensions from the list): --overwrite may replace it.
TEST(SonarFormats, OutputDirectoryRecognisesEveryFormatsFiles) {
  const fs::path dir = xtf::test::temp_dir("sonar_formats_output");
  for (const SonarFormat* f : sonar_formats()) {
    const fs::path out = dir / std::string(f->name);
    {
      OutputDirectory o(out, false);
      std::ofstream(o.file("L1" + std::string(f->extensions.front()))) << "x";
      o.commit();
    }
    EXPECT_EQ(why_not_replaceable_output(out), "") << f->name;
  }
  // A file of no format's extension is not ours.
  std::ofstream(dir / "xtf" / "L1.sdf") << "x";
  EXPECT_NE(why_not_replaceable_output(dir / "xtf"), "");
  fs::remove_all(dir);
}

// `info` of each shipped file: the JSON names the format that identified it, and the text and
// JSON count the same pings as the file's reader.
TEST(SonarFormats, InfoIsTheIdentifiedFormatsSummary) {
  const fs::path dir = xtf::test::temp_dir("sonar_formats_info");
  (void)convert_sonar_file(kData / "xtf" / "golden-tiny.xtf", dir / "tiny.bag", false);
  for (const fs::path& p :
       {kData / "xtf" / "golden-tiny.xtf", kData / "jsf" / "tiny-from-xtf.jsf", dir / "tiny.bag"}) {
    SCOPED_TRACE(p.string());
    const SonarFileInfo info = sonar_file_info(p);
    const auto j = nlohmann::json::parse(info.json);
    const SonarFormat* f = identify_sonar_format(p);
    ASSERT_NE(f, nullptr);
    EXPECT_EQ(j["format"], std::string(f->display_name));
    std::uint64_t pings = 0;
    SideScanRecord r;
    for (auto source = SideScanSource::open(p); source->next(r);) ++pings;
    EXPECT_EQ(j["pings"].get<std::uint64_t>(), pings);
    EXPECT_NE(info.text.find("Sonar pings: " + std::to_string(pings)), std::string::npos)
        << info.text;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth
