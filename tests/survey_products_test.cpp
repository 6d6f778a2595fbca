// SPDX-License-Identifier: MIT
// SurveyProducts: the hook after the mosaic's last use of the bathymetry
// (SurveyProductOptions::after_last_bathymetry_use), through which run_simulation frees the
// scene's grid before the mosaic files are written.
#include "sonarsynth/formats/products/survey_products.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_test_util.hpp"
#include "simulator_test_util.hpp"
#include "sonarsynth/simulator.hpp"
#include "sonarsynth/survey.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

constexpr double kAltitude = 8.0;

// Forwards every call to the products, counting the pings; throws at ping `fail_at` if set.
struct CountingSink final : PingSink {
  explicit CountingSink(PingSink& to, std::size_t fail_at_ping = static_cast<std::size_t>(-1))
      : inner(to), fail_at(fail_at_ping) {}
  void begin(const RunDescription& d) override { inner.begin(d); }
  void begin_line(std::size_t l) override { inner.begin_line(l); }
  void ping(const RenderedPing& p) override {
    if (pings == fail_at) throw std::runtime_error("sink failed");
    inner.ping(p);
    ++pings;
  }
  void end_line(std::size_t l) override { inner.end_line(l); }
  void finish() override { inner.finish(); }
  void abort() noexcept override { inner.abort(); }
  PingSink& inner;
  std::size_t fail_at;
  std::size_t pings = 0;
};

class SurveyProductsTest : public test::ScratchDirTest {
 protected:
  // A sloping seabed with a bump, so that the gridding's ground ranges depend on the grid.
  static std::shared_ptr<Scene> scene() {
    return std::make_shared<Scene>(
        test::make_scene(-60.0, -60.0, 120.0, 0.5, [](double x, double y) {
          return -20.0 + 0.05 * x + 1.5 * std::exp(-((x - 5.0) * (x - 5.0) + y * y) / 20.0);
        }));
  }
  static std::vector<SurveyLine> lines() {
    return {SurveyLine{"a", {{-20.0, -10.0}, {20.0, -10.0}}},
            SurveyLine{"b", {{20.0, 10.0}, {-20.0, 10.0}}}};
  }
  static Survey survey() {
    VehicleConfig v;
    v.speed_m_s = 4.0;
    v.altitude_m = kAltitude;
    return Survey(lines(), v, 0.1, UtcTime{}, 1);
  }
  static SurveyProductOptions options() {
    SurveyProductOptions o;
    o.waterfalls = false;
    o.truth = false;
    o.write_options.overwrite = true;
    return o;
  }
};

TEST_F(SurveyProductsTest, BathymetryHookComesOnceAfterTheLastPingAndTheFilesDoNotNeedTheGrid) {
  const Survey s = survey();
  const SimulationConfig config = test::plain_config();

  // Reference: the grid kept to the end.
  fs::create_directories(dir_ / "kept");
  {
    const auto sc = scene();
    const Simulator sim(sc, config, kAltitude);
    SurveyProducts products(dir_ / "kept", sc, config.sonar, lines(), options());
    sim.run(s, products);
  }

  // The grid freed by the hook, as run_simulation does.
  fs::create_directories(dir_ / "freed");
  {
    const auto sc = scene();
    const Simulator sim(sc, config, kAltitude);
    SurveyProductOptions o = options();
    int calls = 0;
    std::size_t pings_before_hook = 0;
    CountingSink* counting = nullptr;
    o.after_last_bathymetry_use = [&] {
      ++calls;
      pings_before_hook = counting->pings;
      sc->bathymetry.release_heights();
    };
    SurveyProducts products(dir_ / "freed", sc, config.sonar, lines(), o);
    CountingSink sink(products);
    counting = &sink;
    sim.run(s, sink);
    EXPECT_EQ(calls, 1);
    EXPECT_EQ(pings_before_hook, s.total_pings());
    EXPECT_TRUE(sc->bathymetry.empty());
  }

  for (const char* name : {"mosaic.tif", "mosaic_rgb.tif"}) {
    const std::string kept = test::read_text(dir_ / "kept" / name);
    ASSERT_GT(kept.size(), 1000u) << name;
    EXPECT_TRUE(kept == test::read_text(dir_ / "freed" / name)) << name << " differs";
  }
}

TEST_F(SurveyProductsTest, AnAbortedRunDoesNotCallTheBathymetryHook) {
  const Survey s = survey();
  const SimulationConfig config = test::plain_config();
  const auto sc = scene();
  const Simulator sim(sc, config, kAltitude);
  SurveyProductOptions o = options();
  int calls = 0;
  o.after_last_bathymetry_use = [&] { ++calls; };
  SurveyProducts products(dir_, sc, config.sonar, lines(), o);
  CountingSink sink(products, s.total_pings() / 2);
  EXPECT_THROW(sim.run(s, sink), std::runtime_error);
  EXPECT_EQ(calls, 0);
  EXPECT_FALSE(sc->bathymetry.empty());
}

}  // namespace
}  // namespace sonarsynth
