#include <gtest/gtest.h>

#include <cmath>

#include "core/segment_stats.hpp"
#include "core/units.hpp"
#include "sim/gyro_simulator.hpp"

using namespace headingd;

namespace {
drivers::Scenario scenario(const char* name, double hours) { return *drivers::build_scenario(name, 1, hours); }
}  // namespace

TEST(GyroSimulator, SameSeedSameSignal) {
  drivers::GyroSimulator a(scenario("agv", 0.01), 5), b(scenario("agv", 0.01), 5), c(scenario("agv", 0.01), 6);
  core::Sample sa, sb, sc;
  drivers::TruthPoint ta, tb, tc;
  bool differs = false;
  while (!a.done()) {
    a.step(sa, ta);
    b.step(sb, tb);
    c.step(sc, tc);
    ASSERT_EQ(sa.rate_dps, sb.rate_dps);
    differs = differs || sa.rate_dps != sc.rate_dps;
  }
  EXPECT_TRUE(differs);
}

TEST(GyroSimulator, QuantisedClippedAndAtTheStatedRate) {
  drivers::GyroSimulator sim(scenario("agv", 0.05), 2);
  core::Sample s;
  drivers::TruthPoint t;
  std::uint64_t n = 0;
  while (!sim.done()) {
    sim.step(s, t);
    for (int axis = 0; axis < 3; ++axis) {
      const double lsb = s.rate_dps[axis] / 0.00875;
      ASSERT_NEAR(lsb, std::round(lsb), 1e-6);
      ASSERT_LE(std::abs(s.rate_dps[axis]), 245.0);
    }
    ASSERT_DOUBLE_EQ(s.t_s, static_cast<double>(n) / 400.0);
    ++n;
  }
  EXPECT_EQ(n, 72000u);
}

TEST(GyroSimulator, StillNoiseMatchesPaperFigures) {
  // The paper's z axis: per-sample sigma about 11 LSB (0.1 dps) after the chip's low-pass,
  // mean -52 LSB (-0.455 dps).
  drivers::GyroSimulator sim(scenario("still", 0.01), 3);
  core::SegmentStats stats;
  core::Sample s;
  drivers::TruthPoint t;
  while (!sim.done()) {
    sim.step(s, t);
    stats.add(s.rate_dps);
  }
  EXPECT_NEAR(stats.mean_dps().z(), -0.455, 0.01);
  EXPECT_GT(stats.sigma_dps().z(), 0.08);
  EXPECT_LT(stats.sigma_dps().z(), 0.16);
  EXPECT_GT(stats.sigma_dps().x(), 5 * stats.sigma_dps().z());  // x/y are far noisier (0.1 dps/rtHz)
}

TEST(GyroSimulator, PaperScenarioTurnsPointTwoRadianEverySixMinutes) {
  drivers::GyroSimulator sim(scenario("paper12h", 1.0), 1);
  core::Sample s;
  drivers::TruthPoint t;
  double moving_s = 0.0;
  while (!sim.done()) {
    sim.step(s, t);
    if (t.moving) moving_s += 1.0 / 400.0;
  }
  // Turns start at 60 s, then every 360 s, back and forth: 9 complete ones fit in the first
  // hour, ending one turn away from the start. Leg lengths are whole samples, so each turn
  // is 0.2 rad to within a few 1e-5 deg.
  EXPECT_NEAR(t.heading_deg, core::rad_to_deg(0.2), 1e-4);
  EXPECT_GT(moving_s, 9 * 6.0);
  EXPECT_LT(moving_s, 9 * 15.0);
  // Warm-up: the temperature rises and drags the bias along.
  EXPECT_GT(t.temp_c, 22.0 + 5.0);
}

TEST(Scenarios, UnknownNameRefused) { EXPECT_FALSE(drivers::build_scenario("nope", 1, 1.0).has_value()); }
