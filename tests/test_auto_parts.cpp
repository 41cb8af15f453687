// The parts of method auto, each alone: the angle/bias Kalman filter, the temperature
// model, the noise-density estimate, the scale factor, the bias history.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/axis_filter.hpp"
#include "core/bias_history.hpp"
#include "core/level_slope.hpp"
#include "core/noise_density.hpp"
#include "core/scale_factor.hpp"
#include "core/temperature_model.hpp"

using namespace headingd::core;

TEST(AxisFilter, BiasMeasurementCorrectsAngleIntegratedWithWrongBias) {
  AxisFilter filter;
  filter.reset(0.10, 0.01 * 0.01);  // believed bias 0.10, sigma 0.01 dps
  // Still for 100 s while the true bias is 0.11: the integrated angle drifts by -1 deg.
  for (int i = 0; i < 10000; ++i) filter.propagate(0.11, 0.01, 1e-8, 0.0);
  EXPECT_NEAR(filter.angle_deg(), 1.0, 1e-9);  // (0.11 - 0.10) * 100 s
  // A precise bias measurement moves the bias and, through the cross-covariance, takes the
  // angle most of the way back.
  filter.measure_bias(0.11, 1e-8);
  EXPECT_NEAR(filter.bias_dps(), 0.11, 1e-4);
  EXPECT_NEAR(filter.angle_deg(), 0.0, 0.02);
  EXPECT_LT(filter.bias_variance(), 2e-8);
}

TEST(AxisFilter, VarianceGrowsWithWhiteNoiseAndBiasUncertainty) {
  AxisFilter filter;
  filter.reset(0.0, 0.0);
  for (int i = 0; i < 100; ++i) filter.propagate(0.0, 0.01, 0.01 * 0.01, 0.0);  // N = 0.01 for 1 s
  EXPECT_NEAR(filter.angle_variance(), 1e-4, 1e-12);
  AxisFilter uncertain_bias;
  uncertain_bias.reset(0.0, 0.001 * 0.001);
  for (int i = 0; i < 1000; ++i) uncertain_bias.propagate(0.0, 0.01, 0.0, 0.0);  // 10 s
  EXPECT_NEAR(std::sqrt(uncertain_bias.angle_variance()), 0.01, 1e-9);           // sigma_b * T
}

TEST(AxisFilter, ACorrelatedBiasShiftBuildsTheRankOneCovarianceOfASlopeError) {
  // The bias off by k (T - T0) with k ~ N(0, s^2) and T rising 0.1 C/s: after 100 s the
  // angle's error is -k times the integral of (T - T0), and the covariance is s^2 v v' with
  // v = (-integral, T - T0). Propagation makes the angle's share from the bias's; the shifts
  // add what it leaves out, as AutoEstimator::follow_temperature does at each step.
  AxisFilter filter;
  filter.reset(0.0, 0.0);
  const double s2 = 0.003 * 0.003, dt = 0.01;
  double before = 0.0, integral = 0.0;
  for (int i = 1; i <= 10000; ++i) {
    const double after = 0.1 * i * dt;
    integral += before * dt;
    filter.shift_bias(0.0, s2 * (after * after - before * before), -s2 * integral * (after - before));
    filter.propagate(0.0, dt, 0.0, 0.0);
    before = after;
  }
  integral += before * dt;  // the last step's propagation
  const Eigen::Matrix2d& p = filter.state().covariance;
  EXPECT_NEAR(p(1, 1), s2 * 100.0, 1e-9);                        // (10 C)^2
  EXPECT_NEAR(p(0, 1) / (-s2 * integral * 10.0), 1.0, 1e-3);     // integral ~ 500 C s
  EXPECT_NEAR(p(0, 0) / (s2 * integral * integral), 1.0, 1e-3);  // fully correlated
  // A cross term the two variances cannot carry is cut to what they allow; a non-finite one
  // is ignored.
  AxisFilter small;
  small.reset(0.0, 1e-6);
  small.widen_angle(1e-4);
  small.shift_bias(0.0, 0.0, -1.0);
  EXPECT_NEAR(small.state().covariance(0, 1), -1e-5, 1e-15);
  small.shift_bias(0.0, 0.0, std::numeric_limits<double>::infinity());
  EXPECT_NEAR(small.state().covariance(0, 1), -1e-5, 1e-15);
}

TEST(AxisFilter, AngleFixPullsAngle) {
  AxisFilter filter;
  filter.reset(0.0, 1e-6);
  for (int i = 0; i < 100; ++i) filter.propagate(1.0, 0.01, 1e-4, 0.0);
  filter.measure_angle(5.0, 1e-9);
  EXPECT_NEAR(filter.angle_deg(), 5.0, 1e-4);
  EXPECT_LT(filter.angle_variance(), 1e-8);
}

TEST(ScaleFactor, AFixAfterATurnMeasuresItAndOneItCannotExplainDoesNot) {
  // A gyro 1 % high turned 720 degrees: the heading is 7.2 degrees ahead of the fix.
  ScaleFactor scale(0.01);
  EXPECT_NEAR(scale.heading_variance_deg2(720.0), 7.2 * 7.2, 1e-9);
  scale.learn(-7.2, 720.0, 0.01, 0.01);
  EXPECT_TRUE(scale.learned());
  EXPECT_NEAR(scale.estimate(), 0.01, 0.0002);
  EXPECT_NEAR(scale.gain(), 1.0 / 1.01, 0.0002);
  EXPECT_LT(scale.sigma(), 0.001 + 1e-12) << "tightened, to the floor of 0.1 %";
  EXPECT_GE(scale.sigma(), 0.001 - 1e-12);
  ScaleFactor other(0.01);
  other.learn(-7.2, 20.0, 0.01, 0.01);  // too short a turn to tell
  EXPECT_FALSE(other.learned());
  other.learn(-60.0, 720.0, 0.01, 0.01);  // 8 sigma of what 1 % could do: another cause
  EXPECT_FALSE(other.learned());
  EXPECT_EQ(other.estimate(), 0.0);
  ScaleFactor none(0.0);
  none.learn(-7.2, 720.0, 0.01, 0.01);
  EXPECT_FALSE(none.learned()) << "no uncertainty configured, nothing to learn";
  none.restore(0.2, 0.5);  // clamped to what a gyro of this kind can be, no wider than configured
  EXPECT_EQ(none.estimate(), kMaxLearnedScale);
  EXPECT_EQ(none.sigma(), 0.0);
}

TEST(TemperatureModel, LearnsLinearSlopeOnceSpreadIsEnough) {
  TemperatureModel model;
  std::mt19937_64 rng(4);
  std::normal_distribution<double> noise(0.0, 0.003);
  for (int i = 0; i < 6; ++i) model.add(i * 60.0, 25.0 + 0.1 * i, -0.45 + noise(rng), 1e-5);
  EXPECT_FALSE(model.ready()) << "half a degree of spread tells nothing about the slope";
  EXPECT_EQ(model.slope_dps_per_c(30.0), 0.0);
  for (int i = 0; i < 200; ++i) {
    const double temp = 22.0 + 10.0 * (i % 20) / 19.0;
    model.add(400.0 + i * 60.0, temp, -0.45 + 0.0012 * (temp - 25.0) + noise(rng), 1e-5);
  }
  ASSERT_TRUE(model.ready());
  EXPECT_NEAR(model.slope_dps_per_c(25.0), 0.0012, 0.0002);
  EXPECT_NEAR(model.predict_dps(30.0), -0.45 + 0.006, 0.002);
  EXPECT_GT(model.slope_variance(), 0.0);
  EXPECT_LT(std::sqrt(model.slope_variance()), 0.0005);
}

// The datasheet's typical slope (+-0.04 dps/C) through a warm-up: one stop of 3 s segments over
// half a degree already shows it beyond doubt, long before the 2 degC spread the model waits for.
// The same points from segments of separate stops (a creep taken for still between them can
// make such a slope as easily as the temperature) wait for the spread; a slope the unmodelled
// drift (3x 0.003 dps/C) covers waits too.
TEST(TemperatureModel, OneStopShowingASteepSlopeSurelyPutsItInUseBeforeTheSpread) {
  const auto warm_up = [](double slope, bool one_stop) {
    TemperatureModel model;
    std::mt19937_64 rng(7);
    std::normal_distribution<double> noise(0.0, 0.0064);  // a 3 s mean at 0.011 dps/sqrt(Hz)
    for (int i = 0; i < 60; ++i) {
      const double temp = 22.0 + 0.5 * i / 59.0;
      const double run_start_s = one_stop ? 0.0 : 3.0 * i;
      model.add(3.0 * i + 1.5, temp, -0.45 + slope * (temp - 22.0) + noise(rng), 0.0064 * 0.0064, run_start_s);
    }
    return model;
  };
  const TemperatureModel steep = warm_up(0.04, true);
  EXPECT_LT(steep.weighted_span_c(), 0.6);
  ASSERT_TRUE(steep.ready());
  EXPECT_TRUE(steep.run_showed_slope());
  EXPECT_NEAR(steep.slope_dps_per_c(22.0), 0.04, 0.012);
  EXPECT_FALSE(warm_up(0.04, false).ready()) << "sixty one-segment stops: no run showed it";
  EXPECT_FALSE(warm_up(0.005, true).ready()) << "within what the unmodelled drift covers";
  EXPECT_FALSE(warm_up(0.0, true).ready());
  // Restored from its sums (a restart) it waits for the spread or another run again.
  TemperatureModel restored;
  restored.restore(steep.sums(), steep.points());
  EXPECT_FALSE(restored.ready());
}

TEST(TemperatureModel, OldPointsFade) {
  TemperatureModelSettings settings;
  settings.half_life_s = 3600.0;
  TemperatureModel model(settings);
  for (int i = 0; i < 100; ++i) model.add(i * 10.0, 20.0 + (i % 10), 0.002 * (i % 10), 1e-6);  // slope 0.002
  ASSERT_TRUE(model.ready());
  EXPECT_NEAR(model.slope_dps_per_c(25.0), 0.002, 1e-4);
  // A day later the chip's slope has changed; new points soon outweigh the old.
  for (int i = 0; i < 100; ++i) model.add(86400.0 + i * 10.0, 20.0 + (i % 10), -0.001 * (i % 10), 1e-6);
  EXPECT_NEAR(model.slope_dps_per_c(25.0), -0.001, 1e-4);
}

TEST(LevelSlope, AConstantCreepCancelsAndTheSlopeSigmaIsHonest) {
  // 60 segments of 3 s while the chip warms from 24 to 28 C: the level is a 0.2 dps creep on
  // top of a bias that moves -0.004 dps/C, each mean with the white noise of N = 0.01
  // dps/sqrt(Hz). The creep is the same in every segment, so the slope is the bias's; over many
  // such runs the slope lies within two of its own sigmas about 95 % of the time.
  constexpr double kN = 0.01, kSegmentS = 3.0, kSlope = -0.004;
  const Vec3 white = Vec3::Constant(kN * kN);
  std::mt19937_64 rng(12);
  std::normal_distribution<double> noise(0.0, kN / std::sqrt(kSegmentS));
  int within = 0;
  constexpr int kRuns = 400;
  for (int run = 0; run < kRuns; ++run) {
    LevelSlope slope;
    for (int i = 0; i < 60; ++i) {
      const double temp = 24.0 + 4.0 * i / 59.0;
      const double level = 0.2 + (-0.45 + kSlope * (temp - 25.0)) + noise(rng);
      slope.add(kSegmentS, temp, Vec3(0.1 + noise(rng), -0.2 + noise(rng), level));
    }
    LevelSlope::Fit fit;
    ASSERT_TRUE(slope.fit(white, fit));
    EXPECT_NEAR(fit.mean_temp_c, 26.0, 1e-9);
    EXPECT_NEAR(fit.slope_dps_per_c.z(), kSlope, 6.0 * std::sqrt(fit.slope_variance.z()));
    if (std::abs(fit.slope_dps_per_c.z() - kSlope) <= 2.0 * std::sqrt(fit.slope_variance.z())) ++within;
  }
  EXPECT_GT(within, 0.91 * kRuns);
  EXPECT_LT(within, 0.99 * kRuns);
}

TEST(LevelSlope, NoSlopeFromTooFewSegmentsOrOneTemperature) {
  const Vec3 white = Vec3::Constant(1e-4);
  LevelSlope::Fit fit;
  LevelSlope two;
  two.add(3.0, 20.0, Vec3::Zero());
  two.add(3.0, 25.0, Vec3::Ones());
  EXPECT_FALSE(two.fit(white, fit)) << "two points fit any line exactly";
  LevelSlope flat;
  for (int i = 0; i < 10; ++i) flat.add(3.0, 30.0, Vec3::Constant(0.01 * i));
  EXPECT_FALSE(flat.fit(white, fit)) << "one temperature says nothing about a slope";
  LevelSlope unread;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int i = 0; i < 10; ++i) unread.add(3.0, 20.0 + i, Vec3::Constant(0.001 * i));
  unread.add(3.0, nan, Vec3::Constant(50.0));  // no temperature read: left out, not a point
  unread.add(3.0, 25.0, Vec3(nan, 0.0, 0.0));
  ASSERT_TRUE(unread.fit(white, fit));
  EXPECT_NEAR(fit.slope_dps_per_c.z(), 0.001, 1e-12);
}

TEST(NoiseDensity, BlockMeansRecoverWhiteNoiseDensityThroughALowPass) {
  // White noise of density N, sampled at 400 Hz and low-passed like the chip: per-sample sigma
  // is much lower than N * sqrt(fs), but 0.1 s block means still see N.
  const double density = 0.011, fs = 400.0;
  std::mt19937_64 rng(9);
  std::normal_distribution<double> white(0.0, density * std::sqrt(fs));
  const double alpha = std::exp(-2.0 * M_PI * 50.0 / fs);
  double filtered = 0.0;
  NoiseDensity pooled;
  BlockMeans blocks(0.1);
  for (int segment = 0; segment < 100; ++segment) {
    blocks.reset();
    for (int i = 0; i < 1200; ++i) {
      filtered = alpha * filtered + (1.0 - alpha) * white(rng);
      blocks.add(Vec3(filtered, filtered, filtered), 1.0 / fs);
    }
    pooled.add(blocks);
  }
  ASSERT_TRUE(pooled.known());
  EXPECT_NEAR(std::sqrt(pooled.density_squared().z()), density, 0.05 * density);
}

TEST(NoiseDensity, BlockMeansTrendIsTheRampsSlopeAndItsSigmaIsHonestOnNoise) {
  // A ramp of 0.1 dps per block on z: the slope exactly, none on a constant axis.
  BlockMeans ramp(0.1);
  for (int i = 0; i < 1200; ++i) {
    const int block = i / 40;  // the level steps once per block of 40 samples
    ramp.add(Vec3(0.3, 0.0, 0.1 * static_cast<double>(block)), 1.0 / 400.0);
  }
  ASSERT_EQ(ramp.blocks(), 30u);
  EXPECT_NEAR(ramp.trend_per_block().z(), 0.1, 1e-12);
  EXPECT_NEAR(ramp.trend_per_block().x(), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(ramp.index_spread(), 30.0 * (900.0 - 1.0) / 12.0);
  // White noise: the slope over its sigma (a block mean's variance over index_spread) is a
  // standard normal; within 2 sigma on about 95 % of 2000 segments.
  std::mt19937_64 rng(5);
  std::normal_distribution<double> white(0.0, 0.2);
  const double block_variance = 0.2 * 0.2 / 40.0;
  int within = 0;
  for (int segment = 0; segment < 2000; ++segment) {
    BlockMeans blocks(0.1);
    for (int i = 0; i < 1200; ++i) blocks.add(Vec3(white(rng), 0.0, 0.0), 1.0 / 400.0);
    const double z = blocks.trend_per_block().x() / std::sqrt(block_variance / blocks.index_spread());
    within += std::abs(z) <= 2.0 ? 1 : 0;
  }
  EXPECT_NEAR(within / 2000.0, 0.954, 0.015);
}

TEST(BiasHistory, AReturnToAnEarlierLevelOwesTheHeadingTheRawTurnLessThatLevelSinceIt) {
  // The bias is 0.50 throughout. A stop measures it (heading 0); then 100 s of a 1 dps turn and
  // 60 s of a 0.05 dps creep that the estimate took for a stop at 0.55 (heading held), then 200 s
  // of a 1 dps turn integrated with 0.55: the heading says 100 + 0 + 200 x 0.95 = 290 deg, the
  // truth 100 + 3 + 200 = 303 deg.
  BiasHistory history;
  history.measured(10.0, 0.50, 1e-6, 0.0);
  for (int i = 0; i < 100; ++i) history.integrate(1.50, 1.0);
  for (int i = 0; i < 60; ++i) history.integrate(0.55, 1.0);
  history.measured(170.0, 0.55, 1e-6, 100.0);
  for (int i = 0; i < 200; ++i) history.integrate(1.50, 1.0);
  const BiasHistory::Mark run = history.mark();  // a stop at 0.50 restarts the bias
  const auto back = history.correction_for_return(0.50, 1e-6, 0.0, 3.0, run, 370.0, 290.0);
  ASSERT_TRUE(back.has_value());
  EXPECT_NEAR(back->correction_deg, 13.0, 1e-9);
  // Back at the latest level: the turn since it, with that level, is the heading's own.
  const auto same = history.correction_for_return(0.55, 1e-6, 0.0, 3.0, run, 370.0, 290.0);
  ASSERT_TRUE(same.has_value());
  EXPECT_NEAR(same->correction_deg, 0.0, 1e-9);
  // A level no stop measured: no story to tell.
  EXPECT_FALSE(history.correction_for_return(0.40, 1e-6, 0.0, 3.0, run, 370.0, 290.0).has_value());
  // The bias walk widens the match with the time since: 0.475 is 0.025 from 0.50 and 0.55; a walk
  // of 1e-4 dps^2 over the ~360 s since 0.50 puts it within 3 sigma of that one only.
  EXPECT_FALSE(history.correction_for_return(0.475, 0.0, 0.0, 3.0, run, 370.0, 290.0).has_value());
  const auto walked = history.correction_for_return(0.475, 0.0, 1e-4 / 360.0, 3.0, run, 370.0, 290.0);
  ASSERT_TRUE(walked.has_value());
  EXPECT_NEAR(walked->correction_deg, 13.0 + 0.025 * 360.0, 1e-9);
  // After a heading fix the headings kept compare with nothing.
  history.forget();
  EXPECT_FALSE(history.correction_for_return(0.50, 1e-6, 0.0, 3.0, run, 370.0, 290.0).has_value());
}

TEST(BiasHistory, ABiasCarriedStepByStepLeavesItsFirstLevelBehindForAReturn) {
  // The platform stands still with the bias at 0.50 throughout, while the estimate is carried
  // away from it 0.001 dps per 10 s segment (a temperature model with a wrong slope), each step
  // within 2 sigma of the one before. Measured points joined to the latest merge the whole walk
  // into its last point, 0.599, and a return to 0.50 finds nothing; carried, a point joins a
  // level only if it agrees with the level's first point, so 0.500-0.502 stay one level.
  const auto walk = [](bool carried, double& heading_deg, double& heading_at_first_level_deg) {
    BiasHistory history;
    for (int k = 0; k < 100; ++k) {
      const double carried_dps = 0.50 + 0.001 * k;
      history.measured(10.0 * k, carried_dps, 1e-6, heading_deg, carried);
      if (k == 2) heading_at_first_level_deg = heading_deg;  // the first level's latest point
      for (int i = 0; i < 10; ++i) {
        history.integrate(0.50, 1.0);  // the raw rate: the bias alone
        heading_deg += 0.50 - carried_dps;
      }
    }
    return history;
  };
  double heading_deg = 0.0, heading_at_first_level_deg = 0.0;
  const BiasHistory carried = walk(true, heading_deg, heading_at_first_level_deg);
  const auto back = carried.correction_for_return(0.50, 1e-6, 0.0, 3.0, carried.mark(), 1000.0, heading_deg);
  ASSERT_TRUE(back.has_value());
  // Had the bias been 0.50 since that point the heading would not have moved.
  EXPECT_NEAR(back->correction_deg, heading_at_first_level_deg - heading_deg, 1e-9);
  EXPECT_GT(back->correction_deg, 40.0);
  // A level inside the walk matches the step nearest it, not the walk's start.
  const auto middle = carried.correction_for_return(0.55, 1e-6, 0.0, 3.0, carried.mark(), 1000.0, heading_deg);
  ASSERT_TRUE(middle.has_value());
  EXPECT_LT(std::abs(middle->correction_deg), std::abs(back->correction_deg));
  // The same steps measured stop by stop with nothing carrying the estimate are a bias that
  // drifted for real: one level, the latest, and no return to where it began.
  double measured_heading_deg = 0.0, unused_deg = 0.0;
  const BiasHistory measured = walk(false, measured_heading_deg, unused_deg);
  EXPECT_FALSE(
      measured.correction_for_return(0.50, 1e-6, 0.0, 3.0, measured.mark(), 1000.0, measured_heading_deg).has_value());
}

TEST(BiasHistory, NoReturnAcrossALongStopAtAnotherLevelAndTheWalksShareInItsVariance) {
  // A stop at 0.50 (60 s held), a drive, a stop at 0.53 held for 300 s, a drive, then a quiet run
  // at 0.50: had the bias never moved, the 300 s stop at 0.53 would have been a creep held that
  // long. With a refuting span of 270 s no return; with 400 s (or none) the return to 0.50.
  BiasHistory history;
  history.measured(60.0, 0.50, 1e-6, 0.0, false, 60.0);
  for (int i = 0; i < 100; ++i) history.integrate(1.50, 1.0);
  for (int k = 1; k <= 100; ++k) history.measured(160.0 + 3.0 * k, 0.53, 1e-6, 100.0, false, 3.0 * k);
  for (int i = 0; i < 100; ++i) history.integrate(1.53, 1.0);
  const BiasHistory::Mark run = history.mark();
  EXPECT_FALSE(history.correction_for_return(0.50, 1e-6, 0.0, 3.0, run, 560.0, 200.0, 270.0).has_value());
  const auto back = history.correction_for_return(0.50, 1e-6, 0.0, 3.0, run, 560.0, 200.0, 400.0);
  ASSERT_TRUE(back.has_value());
  EXPECT_TRUE(history.correction_for_return(0.50, 1e-6, 0.0, 3.0, run, 560.0, 200.0).has_value());
  // Integrated over the 200 s since 0.50's point: the level's variance times T^2, and the walk's
  // integral, q T^3 / 3, which a match over hours makes larger than any correction it proposes.
  const double q = 1e-8;
  const auto walked = history.correction_for_return(0.50, 1e-6, q, 3.0, run, 560.0, 200.0, 400.0);
  ASSERT_TRUE(walked.has_value());
  EXPECT_NEAR(back->variance_deg2, 1e-6 * 200.0 * 200.0, 1e-9);
  EXPECT_NEAR(walked->variance_deg2, 1e-6 * 200.0 * 200.0 + q * 200.0 * 200.0 * 200.0 / 3.0, 1e-9);
  EXPECT_NEAR(walked->correction_deg, back->correction_deg, 1e-12);
}

TEST(BiasHistory, StopsAtOneLevelKeepOnlyTheLatestAndTheOldestLevelsGo) {
  BiasHistory history;
  history.measured(0.0, 0.50, 1e-6, 0.0);
  for (int i = 0; i < 100; ++i) history.integrate(0.60, 1.0);
  history.measured(100.0, 0.5001, 1e-6, 5.0);  // the same level again, later: the correction counts from here
  for (int i = 0; i < 50; ++i) history.integrate(0.60, 1.0);
  const auto back = history.correction_for_return(0.50, 1e-6, 0.0, 3.0, history.mark(), 150.0, 5.0);
  ASSERT_TRUE(back.has_value());
  EXPECT_NEAR(back->correction_deg, (0.60 - 0.50) * 50.0, 1e-9);
  // Hundreds of distinct levels later the first is gone; the bounded memory never allocates.
  for (int i = 1; i <= 300; ++i) history.measured(150.0 + i, 0.50 + 0.01 * i, 1e-8, 5.0);
  EXPECT_FALSE(history.correction_for_return(0.50, 1e-8, 0.0, 3.0, history.mark(), 500.0, 5.0).has_value());
  EXPECT_TRUE(history.correction_for_return(3.50, 1e-8, 0.0, 3.0, history.mark(), 500.0, 5.0).has_value());
  // Non-finite input is no level.
  history.measured(600.0, std::numeric_limits<double>::quiet_NaN(), 1e-8, 5.0);
  EXPECT_FALSE(
      history
          .correction_for_return(std::numeric_limits<double>::quiet_NaN(), 1e-8, 0.0, 3.0, history.mark(), 700.0, 5.0)
          .has_value());
}
