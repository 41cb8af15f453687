#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

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

// The random world (issue 12's sweep): every draw within its stated range, every kind of
// world turning up across seeds, and the same seed the same world.
TEST(Scenarios, RandomWorldsStayWithinTheirRangesAndVary) {
  int started_moving = 0, conveyor = 0, cold_start = 0, heater_or_ramp = 0;
  std::set<double> rates;
  double shortest_stop_s = 1e9, longest_stop_s = 0.0, fastest_turn_dps = 0.0, slowest_creep_dps = 1e9;
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    const drivers::Scenario s = *drivers::build_scenario("random", seed, 2.0);
    const drivers::NoiseModel& n = s.noise;
    rates.insert(n.rate_hz);
    EXPECT_NEAR(static_cast<double>(s.total_samples) / n.rate_hz, 7200.0, 1.0);
    EXPECT_GE(n.arw_dps_rt_hz.z(), 0.004);
    EXPECT_LE(n.arw_dps_rt_hz.z(), 0.02);
    EXPECT_LE(n.bias_per_c_dps.cwiseAbs().maxCoeff(), 0.01);
    EXPECT_LE(std::abs(n.scale_factor_error), 0.005);
    EXPECT_GE(n.bias_instability_dps.minCoeff() * 3600.0, 1.0 - 1e-9);
    EXPECT_LE(n.bias_instability_dps.maxCoeff() * 3600.0, 10.0 + 1e-9);
    cold_start += n.warmup_rise_c >= 10.0;
    for (std::size_t k = 1; k < n.temp_knots_c.size(); ++k) {
      const double slope_c_per_h = (n.temp_knots_c[k].second - n.temp_knots_c[k - 1].second) /
                                   (n.temp_knots_c[k].first - n.temp_knots_c[k - 1].first) * 3600.0;
      heater_or_ramp += std::abs(slope_c_per_h) > 1.0;
    }
    ASSERT_FALSE(s.legs.empty());
    started_moving += s.legs.front().moving;
    for (const drivers::Leg& leg : s.legs) {
      const double duration_s = static_cast<double>(leg.samples) / n.rate_hz;
      if (!leg.moving) {
        conveyor += leg.vibration_dps > 0.0;
        if (&leg != &s.legs.back()) shortest_stop_s = std::min(shortest_stop_s, duration_s);
        longest_stop_s = std::max(longest_stop_s, duration_s);
      } else {
        fastest_turn_dps = std::max(fastest_turn_dps, std::abs(leg.rate_dps.z()));
        if (std::abs(leg.rate_dps.z()) > 0.0)
          slowest_creep_dps = std::min(slowest_creep_dps, std::abs(leg.rate_dps.z()));
      }
    }
  }
  EXPECT_EQ(rates, (std::set<double>{100.0, 200.0, 400.0, 800.0}));
  EXPECT_GT(started_moving, 0);
  EXPECT_LT(started_moving, 30);
  EXPECT_GT(conveyor, 0);
  EXPECT_GT(cold_start, 20);
  EXPECT_GT(heater_or_ramp, 60);
  EXPECT_LT(shortest_stop_s, 3.0);
  EXPECT_GT(longest_stop_s, 600.0);
  EXPECT_LE(fastest_turn_dps, 60.0 + 1e-9);
  EXPECT_GT(fastest_turn_dps, 40.0);
  EXPECT_LT(slowest_creep_dps, 0.05);

  // Same seed, same world; and the simulator draws from it alike.
  const auto a = *drivers::build_scenario("random", 7, 0.2), b = *drivers::build_scenario("random", 7, 0.2);
  ASSERT_EQ(a.legs.size(), b.legs.size());
  EXPECT_EQ(a.noise.temp_knots_c, b.noise.temp_knots_c);
  drivers::GyroSimulator sa(a, 7), sb(b, 7);
  core::Sample x, y;
  drivers::TruthPoint tx, ty;
  while (!sa.done()) {
    sa.step(x, tx);
    sb.step(y, ty);
    ASSERT_EQ(x.rate_dps, y.rate_dps);
    ASSERT_EQ(tx.bias_z_dps, ty.bias_z_dps);
  }
}
