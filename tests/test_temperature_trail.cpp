// TemperatureTrail: rejected stops whose levels follow the temperature on a line explain a
// restart; stops a line does not explain (creeps, a flat drift, too little spread) do not.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/temperature_trail.hpp"

using headingd::core::TemperatureTrail;
using headingd::core::Vec3;

namespace {

// The simulated L3GD20H's white noise on z, x/y noisier (agv: 0.011 and 0.1 dps/sqrt(Hz)).
const Vec3 kWhite(0.1 * 0.1, 0.1 * 0.1, 0.011 * 0.011);

TemperatureTrail::Stop stop_at(double temp_c, double slope_dps_per_c, double duration_s, std::mt19937& random,
                               double offset_dps = 0.0) {
  std::normal_distribution<double> unit;
  Vec3 level = Vec3(0.3, -0.2, -0.43) + Vec3::Constant(slope_dps_per_c * (temp_c - 22.0) + offset_dps);
  for (int a = 0; a < 3; ++a) level[a] += std::sqrt(kWhite[a] / duration_s) * unit(random);
  return {.level_dps = level, .temp_c = temp_c, .duration_s = duration_s};
}

}  // namespace

TEST(TemperatureTrail, StopsOnTheDatasheetsSlopeThroughAWarmUpExplainTheRestart) {
  // Four stops of 8-50 s over 1.2 C of a warm-up at 0.04 dps/C: the line, within its own sigma.
  for (unsigned seed = 1; seed <= 20; ++seed) {
    std::mt19937 random(seed);
    TemperatureTrail trail;
    trail.add(stop_at(22.4, 0.04, 30.0, random));
    trail.add(stop_at(22.8, 0.04, 8.0, random));
    trail.add(stop_at(23.2, 0.04, 50.0, random));
    const auto line = trail.explain(stop_at(23.6, 0.04, 9.0, random), kWhite, 0.0);
    ASSERT_TRUE(line) << "seed " << seed;
    EXPECT_EQ(line->stops, 4u);
    EXPECT_DOUBLE_EQ(line->coldest_c, 22.4);
    EXPECT_DOUBLE_EQ(line->warmest_c, 23.6);
    EXPECT_NEAR(line->slope_dps_per_c.z(), 0.04, 4.0 * std::sqrt(line->slope_variance.z()));
    EXPECT_LT(std::sqrt(line->slope_variance.z()), 0.01);
    EXPECT_NEAR(line->at(22.0).z(), -0.43, 4.0 * std::sqrt(line->variance_at(22.0).z()));
  }
}

TEST(TemperatureTrail, AnOlderStopOffTheLineDoesNotHideTheLatestOnes) {
  std::mt19937 random(3);
  TemperatureTrail trail;
  trail.add(stop_at(22.0, 0.04, 20.0, random, 0.3));  // a slow curve held quiet
  trail.add(stop_at(22.4, 0.04, 30.0, random));
  trail.add(stop_at(22.8, 0.04, 30.0, random));
  trail.add(stop_at(23.2, 0.04, 30.0, random));
  const auto line = trail.explain(stop_at(23.6, 0.04, 30.0, random), kWhite, 0.0);
  ASSERT_TRUE(line);
  EXPECT_EQ(line->stops, 4u);
}

TEST(TemperatureTrail, CreepsFlatDriftAndShallowSlopesExplainNothing) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> creep(-0.05, 0.05);
  int explained_creeps = 0;
  for (int trial = 0; trial < 200; ++trial) {
    TemperatureTrail trail;
    for (int i = 0; i < 5; ++i) trail.add(stop_at(22.0 + 0.3 * i, 0.0, 30.0, random, creep(random)));
    if (trail.explain(stop_at(23.5, 0.0, 30.0, random, creep(random)), kWhite, 0.0)) ++explained_creeps;
  }
  // Creeps of up to 0.05 dps at random: a line with every stop within 3 sigma and a steep, sure
  // slope is rare (70 in 2000 such trails; 168 with three stops, 6 with four over 1 C, which
  // found the datasheet's drift one stop later and lost 3-8 deg more before it on the agv worlds).
  EXPECT_LE(explained_creeps, 12);

  TemperatureTrail flat;  // the same level at every temperature: no slope to show
  for (int i = 0; i < 5; ++i) flat.add(stop_at(22.0 + 0.3 * i, 0.0, 30.0, random, 0.02));
  EXPECT_FALSE(flat.explain(stop_at(23.5, 0.0, 30.0, random, 0.02), kWhite, 0.0));

  TemperatureTrail shallow;  // issue 12's random worlds' coefficients: the model's drift covers them
  for (int i = 0; i < 5; ++i) shallow.add(stop_at(22.0 + 0.3 * i, 0.005, 30.0, random));
  EXPECT_FALSE(shallow.explain(stop_at(23.5, 0.005, 30.0, random), kWhite, 0.0));
}

TEST(TemperatureTrail, TooFewStopsOrTooLittleSpreadExplainNothing) {
  std::mt19937 random(11);
  TemperatureTrail three;  // three stops: one residual's worth of evidence against a creep
  three.add(stop_at(22.0, 0.04, 30.0, random));
  three.add(stop_at(23.0, 0.04, 30.0, random));
  EXPECT_FALSE(three.explain(stop_at(24.0, 0.04, 30.0, random), kWhite, 0.0));
  three.add(stop_at(24.0, 0.04, 30.0, random));  // the fourth makes a line
  EXPECT_TRUE(three.explain(stop_at(25.0, 0.04, 30.0, random), kWhite, 0.0));

  TemperatureTrail narrow;  // 0.4 C: a slope over a fraction of a degree is no line yet
  for (int i = 0; i < 4; ++i) narrow.add(stop_at(22.0 + 0.1 * i, 0.04, 30.0, random));
  EXPECT_FALSE(narrow.explain(stop_at(22.4, 0.04, 30.0, random), kWhite, 0.0));

  TemperatureTrail broken;  // non-finite stops are not kept
  broken.add({.level_dps = Vec3::Constant(NAN), .temp_c = 22.0, .duration_s = 30.0});
  broken.add({.level_dps = Vec3::Zero(), .temp_c = NAN, .duration_s = 30.0});
  EXPECT_EQ(broken.size(), 0u);
}

TEST(TemperatureTrail, WholeDegreeTemperaturesWidenTheLine) {
  std::mt19937 random(5);
  TemperatureTrail trail;
  for (int i = 0; i < 4; ++i) trail.add(stop_at(22.0 + 0.4 * i, 0.04, 40.0, random));
  const auto current = stop_at(23.8, 0.04, 40.0, random);
  const auto exact = trail.explain(current, kWhite, 0.0);
  const auto rounded = trail.explain(current, kWhite, 1.0 / 12.0);
  ASSERT_TRUE(exact);
  ASSERT_TRUE(rounded);
  EXPECT_GT(rounded->slope_variance.z(), 2.0 * exact->slope_variance.z());
}
