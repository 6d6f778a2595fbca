// SPDX-License-Identifier: MIT
#include "sonarsynth/survey.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "sonarsynth/error.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth {
namespace {

// A north-up grid over x in [x0, x0 + (cols-1) cell], y in [y0, y0 + (rows-1) cell].
HeightGrid grid(double x0, double y0, std::size_t cols, std::size_t rows, double cell,
                const std::function<double(double, double)>& h) {
  GridGeometry g;
  g.cols = cols;
  g.rows = rows;
  g.dx_m = cell;
  g.dy_m = -cell;
  g.x0_m = x0;
  g.y0_m = y0 + static_cast<double>(rows - 1) * cell;
  std::vector<float> z(g.size());
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < cols; ++c) {
      z[r * cols + c] = static_cast<float>(
          h(g.x_of_col(static_cast<double>(c)), g.y_of_row(static_cast<double>(r))));
    }
  }
  return HeightGrid(g, std::move(z));
}

const UtcTime kT0 = std::chrono::sys_days(std::chrono::year(2026) / 1 / 1);

TEST(SurveyMotion, AltitudeControllerStepResponseIsFirstOrder) {
  // A 5 m step up at y = 0 (heights -20 below, -15 from the node at y = 0 on: a bilinear ramp
  // from y = -0.1 to 0). Heading north at 2 m/s with a 3 s time constant: after the ramp the
  // sensor's height is that of a first-order lag driven by the ramp,
  //   z = A - 20 + 5 [1 - (tau / D) (exp(-(t - tb) / tau) - exp(-(t - ta) / tau))],
  // ta, tb the times at the ramp's ends, D = tb - ta; A before it.
  const HeightGrid seabed = grid(-5.0, -100.0, 101, 4001, 0.1,
                                 [](double, double y) { return y < -1e-9 ? -20.0 : -15.0; });
  VehicleConfig v;
  v.speed_m_s = 2.0;
  v.altitude_m = 8.0;
  v.altitude_time_constant_s = 3.0;
  const Survey s({{"n", {{0.0, -50.0}, {0.0, 250.0}}}}, v, 0.1, kT0, 1);
  const double tau = 3.0, ta = (50.0 - 0.1) / 2.0, tb = 50.0 / 2.0, d = tb - ta;
  int checked = 0;
  for (std::uint64_t i = 0; i < s.total_pings(); i += 7) {
    const PingPose p = s.pose(i, seabed);
    const double t = 0.1 * static_cast<double>(i);
    if (t <= ta) {
      ASSERT_NEAR(p.sensor_z_m, -12.0, 1e-4) << t;
      ASSERT_NEAR(p.altitude_m, 8.0, 1e-4) << t;
    } else if (t >= tb) {
      const double step = 1.0 - tau / d * (std::exp(-(t - tb) / tau) - std::exp(-(t - ta) / tau));
      ASSERT_NEAR(p.sensor_z_m, -12.0 + 5.0 * step, 5e-3) << t;
      // The altitude dips after the step and recovers: 8 - 5 exp(-t / tau) about.
      ASSERT_NEAR(p.altitude_m, 8.0 - 5.0 * (1.0 - step), 5e-3) << t;
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
  // One time constant after the step: 1 - 1/e of it.
  const PingPose one_tau =
      s.pose(static_cast<std::uint64_t>(std::lround((tb + tau) / 0.1)), seabed);
  EXPECT_NEAR(one_tau.sensor_z_m - (-12.0), 5.0 * (1.0 - std::exp(-1.0)), 0.05);
  // Without a time constant the sensor follows the seabed exactly.
  v.altitude_time_constant_s = 0.0;
  const Survey exact({{"n", {{0.0, -50.0}, {0.0, 250.0}}}}, v, 0.1, kT0, 1);
  EXPECT_NEAR(
      exact.pose(static_cast<std::uint64_t>(std::lround((tb + tau) / 0.1)), seabed).altitude_m, 8.0,
      1e-9);
}

TEST(SurveyMotion, AltitudeControllerLagsAlongASlope) {
  // Steady climb: h rises at slope g along the track, so dh/dt = g v and a first-order lag
  // trails by tau: the altitude settles at A - g v tau.
  const double g = 0.05;
  const HeightGrid seabed =
      grid(-5.0, -100.0, 11, 401, 1.0, [g](double, double y) { return -30.0 + g * y; });
  VehicleConfig v;
  v.speed_m_s = 1.5;
  v.altitude_m = 10.0;
  v.altitude_time_constant_s = 4.0;
  const Survey s({{"n", {{0.0, 0.0}, {0.0, 250.0}}}}, v, 0.2, kT0, 1);
  for (std::uint64_t i = 100; i < s.total_pings(); i += 50) {
    EXPECT_NEAR(s.pose(i, seabed).altitude_m, 10.0 - g * 1.5 * 4.0, 2e-3) << i;
  }
}

// RMS of x and RMS of its central difference over step dt.
void rms_and_rate(const std::vector<double>& x, double dt, double* rms, double* rate_rms) {
  double mean = 0.0;
  for (double a : x) mean += a;
  mean /= static_cast<double>(x.size());
  double s2 = 0.0, d2 = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    s2 += (x[i] - mean) * (x[i] - mean);
    if (i > 0 && i + 1 < x.size()) {
      const double d = (x[i + 1] - x[i - 1]) / (2.0 * dt);
      d2 += d * d;
    }
  }
  *rms = std::sqrt(s2 / static_cast<double>(x.size()));
  *rate_rms = std::sqrt(d2 / static_cast<double>(x.size() - 2));
}

TEST(SurveyMotion, WanderHasTheConfiguredRmsAndPeriod) {
  // Over 100 wander periods: RMS = the value given, RMS(d/dt) / RMS = 2 pi / period (the
  // wanders' mean square angular frequency), up to the finite line (beats of the five
  // sinusoids) and the central difference (sinc bias under 2 % at 40 pings per period).
  const HeightGrid seabed = grid(-10.0, -10.0, 21, 1021, 1.0, [](double, double) { return -30.0; });
  for (const bool depth_mode : {false, true}) {
    VehicleConfig v;
    v.speed_m_s = 0.5;
    v.altitude_m = 10.0;
    if (depth_mode) {
      v.depth_mode = VehicleConfig::DepthMode::kDepth;
      v.depth_m = 12.0;
    }
    v.disturbance.altitude_wander_m = 0.8;
    v.disturbance.heading_wander_rad = rad_from_deg(2.0);
    v.disturbance.wander_period_s = 20.0;
    const double dt = 0.5;
    const Survey s({{"n", {{0.0, 0.0}, {0.0, 1000.0}}}}, v, dt, kT0, 9);
    ASSERT_GE(s.total_pings(), 4000u);  // 2000 s
    std::vector<double> z, heading;
    for (std::uint64_t i = 0; i < s.total_pings(); ++i) {
      const PingPose p = s.pose(i, seabed);
      z.push_back(p.sensor_z_m);
      heading.push_back(p.heading_rad);
      ASSERT_NEAR(p.altitude_m, p.sensor_z_m + 30.0, 1e-9);
    }
    double rms = 0.0, rate = 0.0;
    rms_and_rate(z, dt, &rms, &rate);
    EXPECT_NEAR(rms / 0.8, 1.0, 0.1) << depth_mode;
    EXPECT_NEAR(rate / rms / (2.0 * kPi / 20.0), 1.0, 0.1) << depth_mode;
    rms_and_rate(heading, dt, &rms, &rate);
    EXPECT_NEAR(rms / rad_from_deg(2.0), 1.0, 0.1);
    EXPECT_NEAR(rate / rms / (2.0 * kPi / 20.0), 1.0, 0.1);
  }
}

TEST(SurveyMotion, WanderIsSeededAndOffByDefault) {
  const HeightGrid seabed = grid(-10.0, -10.0, 21, 121, 1.0, [](double, double) { return -30.0; });
  VehicleConfig v;
  EXPECT_FALSE(v.disturbance.any());
  const Survey plain({{"n", {{0.0, 0.0}, {0.0, 100.0}}}}, v, 0.5, kT0, 9);
  EXPECT_EQ(plain.pose(50, seabed).sensor_z_m, -20.0);
  v.disturbance.altitude_wander_m = 0.5;
  const Survey a({{"n", {{0.0, 0.0}, {0.0, 100.0}}}}, v, 0.5, kT0, 9);
  const Survey b({{"n", {{0.0, 0.0}, {0.0, 100.0}}}}, v, 0.5, kT0, 10);
  EXPECT_EQ(a.pose(50, seabed).sensor_z_m, a.pose(50, seabed).sensor_z_m);
  EXPECT_NE(a.pose(50, seabed).sensor_z_m, b.pose(50, seabed).sensor_z_m);
}

TEST(SurveyMotion, ValidationNamesTheKey) {
  VehicleConfig v;
  v.altitude_time_constant_s = -1.0;
  EXPECT_THROW(v.validate(), InputError);
  v = VehicleConfig{};
  v.disturbance.wander_period_s = 0.0;
  EXPECT_THROW(v.validate(), InputError);
  v = VehicleConfig{};
  v.disturbance.altitude_wander_m = -0.1;
  try {
    v.validate();
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("altitude_m >= 0"), std::string::npos) << e.what();
  }
}

TEST(SurveyLines, ANonFiniteWaypointIsNamedWithItsValue) {
  for (const double bad : {std::nan(""), double{INFINITY}}) {
    SurveyLine l{"a", {{0.0, 0.0}, {10.0, 0.0}, {bad, 5.0}}};
    try {
      Survey s({l}, VehicleConfig{}, 0.1, UtcTime{}, 1);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("line 'a' waypoint 2 = ("), std::string::npos) << m;
      EXPECT_NE(m.find(std::isnan(bad) ? "nan" : "inf"), std::string::npos) << m;
      EXPECT_EQ(m.find("repeats"), std::string::npos) << m;
    }
  }
}

}  // namespace
}  // namespace sonarsynth
