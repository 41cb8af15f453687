// The heading sigma calibrated by the run's own stops (core/stop_innovations.hpp): the part
// on its own, then method auto on crafted runs whose bias moves more, or less, between stops
// than the filter was told.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/estimator.hpp"
#include "core/stop_innovations.hpp"

using namespace headingd::core;

TEST(StopInnovations, ScalesByWhatTheStopsFoundBeyondTheirOwnNoiseOverWhatTheFilterPredicted) {
  StopInnovations s;
  EXPECT_DOUBLE_EQ(s.variance_scale(), 1.0);
  // Bias variance 1e-4 predicted, the mean's noise 1e-4; the bias found 0.03 away: it moved by
  // a variance of 9e-4 - 1e-4, eight times the prediction; half-way with the prior: 4.5.
  s.add(0.03, 1e-4, 1e-4);
  EXPECT_NEAR(s.variance_scale(), 4.5, 1e-12);
  // Eight stops that found it exactly as far as predicted (v^2 = P + r).
  for (int i = 0; i < 8; ++i) s.add(std::sqrt(2e-4), 1e-4, 1e-4);
  EXPECT_NEAR(s.variance_scale(), (8e-4 + 8e-4 + 1e-4) / (9e-4 + 1e-4), 1e-12);
  s.add(std::nan(""), 1e-4, 1e-4);  // not counted
  s.add(0.01, 0.0, 1e-4);           // nothing predicted: nothing to scale
  s.add(0.01, 1e-4, -1.0);
  EXPECT_EQ(s.stops(), 9u);
  // Stops that all find the bias exactly where predicted: the filter was too cautious, but the
  // sigma is only ever widened (what else it holds, the stops do not measure).
  for (int i = 0; i < 100; ++i) s.add(0.0, 1e-4, 1e-4);
  EXPECT_DOUBLE_EQ(s.variance_scale(), 1.0);
}

namespace {

constexpr double kHz = 400.0;

// A start-up of 30 s, then `cycles` times a drive of 60 s (turning at 10 dps with vibration)
// and a stop of 30 s. Before each drive the true z bias moves by `shift_dps`, up and down in
// turn (a shock, a trim change: nothing the bias walk or a temperature explains). Per drive, at its end (just before
// the stop measures the bias), the heading error and the sigma shown.
struct DriveRun {
  std::vector<double> error_deg, sigma_deg;
  std::vector<double> heading_deg;  // at the same moments
};
DriveRun drive_and_stop(EstimatorSettings settings, double shift_dps, int cycles) {
  settings.automatic.scale_factor_sigma = 0.0;  // the signal has no scale error: the bias's share alone
  Estimator estimator(settings);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  double truth_deg = 0.0, bias_z = -0.45, t_s = 0.0;
  long index = 0;
  DriveRun run;
  const auto step = [&](double rate_dps, double shake_dps) {
    Sample s;
    s.t_s = t_s = static_cast<double>(index) / kHz;
    const double shake = shake_dps * noise(rng);
    s.rate_dps = Vec3(0.3 + 0.05 * noise(rng) + shake, -0.2 + 0.05 * noise(rng) + shake,
                      bias_z + rate_dps + 0.2 * noise(rng) + 0.3 * shake);
    if (index++ > 0) truth_deg += rate_dps / kHz;
    estimator.update(s);
  };
  const auto seconds = [](double s) { return static_cast<long>(std::lround(s * kHz)); };
  for (long i = 0; i < seconds(30.0); ++i) step(0.0, 0.0);
  for (int c = 0; c < cycles; ++c) {
    bias_z += c % 2 == 0 ? shift_dps : -shift_dps;
    for (long i = 0; i < seconds(60.0); ++i) step(10.0, 0.5);
    run.error_deg.push_back(truth_deg - estimator.last().heading_deg);
    run.sigma_deg.push_back(estimator.last().heading_sigma_deg);
    run.heading_deg.push_back(estimator.last().heading_deg);
    for (long i = 0; i < seconds(30.0); ++i) step(0.0, 0.0);
  }
  return run;
}

int within_two_sigma(const DriveRun& run) {
  int n = 0;
  for (std::size_t i = 0; i < run.error_deg.size(); ++i) n += std::abs(run.error_deg[i]) <= 2.0 * run.sigma_deg[i];
  return n;
}

std::string describe(const DriveRun& run) {
  std::string out;
  for (std::size_t i = 0; i < run.error_deg.size(); ++i)
    out += std::to_string(run.error_deg[i]) + "/" + std::to_string(run.sigma_deg[i]) + " ";
  return out;
}

// The same signal into two estimators, one calibrating its sigma by the stops and one not:
// a stationary platform's z bias of -0.45 dps (plus `bias_shift_dps`), its white noise, and
// while driving a vibration that reaches every axis.
struct TwinRun {
  Estimator calibrated, plain;
  std::mt19937_64 rng;
  std::normal_distribution<double> noise{0.0, 1.0};
  long index = 0;
  double bias_shift_dps = 0.0;
  double truth_deg = 0.0;  // the heading turned, integrated as the estimators do (from the 2nd sample)

  TwinRun(const EstimatorSettings& settings, unsigned seed)
      : calibrated(settings), plain(without_calibration(settings)), rng(seed) {}
  static EstimatorSettings without_calibration(EstimatorSettings settings) {
    settings.automatic.calibrate_sigma = false;
    return settings;
  }
  void run(double seconds, double rate_dps, double shake_dps) {
    for (long i = 0; i < std::lround(seconds * kHz); ++i) {
      Sample s;
      if (index > 0) truth_deg += rate_dps / kHz;
      s.t_s = static_cast<double>(index++) / kHz;
      const double shake = shake_dps * noise(rng);
      s.rate_dps = Vec3(0.3 + 0.05 * noise(rng) + shake, -0.2 + 0.05 * noise(rng) + shake,
                        -0.45 + bias_shift_dps + rate_dps + 0.2 * noise(rng) + 0.3 * shake);
      calibrated.update(s);
      plain.update(s);
    }
  }
  // A fix from the truth with its variance, to both.
  void fix(double variance_deg2) {
    calibrated.set_heading(truth_deg, variance_deg2);
    plain.set_heading(truth_deg, variance_deg2);
  }
  void hint(MotionHint h) {
    calibrated.set_motion_hint(h);
    plain.set_motion_hint(h);
  }
};

}  // namespace

TEST(StopInnovations, ABiasThatMovesMoreBetweenStopsThanTheFilterAllowsWidensTheSigmaShown) {
  // 0.012 dps per drive, two sigma of a stop's first segment: each stop is accepted at once,
  // yet the filter (walk 1e-4 dps/sqrt(s): 0.001 over a drive) is sure of every bias it takes.
  EstimatorSettings calibrated, filter_only;
  filter_only.automatic.calibrate_sigma = false;
  const DriveRun with = drive_and_stop(calibrated, 0.012, 8);
  const DriveRun without = drive_and_stop(filter_only, 0.012, 8);
  SCOPED_TRACE("calibrated: " + describe(with) + "\nfilter's own: " + describe(without));
  ASSERT_EQ(with.heading_deg, without.heading_deg);  // the sigma only: the estimates are the same
  EXPECT_LE(within_two_sigma(without), 2);
  EXPECT_GE(within_two_sigma(with), 6);
  EXPECT_GT(with.sigma_deg.back(), 1.5 * without.sigma_deg.back());
}

TEST(StopInnovations, ABiasSteadierThanTheFilterWasToldLeavesTheFiltersSigma) {
  // The true bias does not move; the filter was told a walk 100 times the default's. The stops
  // find less than predicted, which says nothing of the white noise's share in the heading
  // variance: the sigma shown is the filter's own, and covers every drive end.
  EstimatorSettings calibrated, filter_only;
  calibrated.automatic.bias_walk_dps_rt_s = filter_only.automatic.bias_walk_dps_rt_s = 1e-2;
  filter_only.automatic.calibrate_sigma = false;
  const DriveRun with = drive_and_stop(calibrated, 0.0, 8);
  const DriveRun without = drive_and_stop(filter_only, 0.0, 8);
  SCOPED_TRACE("calibrated: " + describe(with) + "\nfilter's own: " + describe(without));
  ASSERT_EQ(with.heading_deg, without.heading_deg);
  // The first drive end may carry a few percent: the start-up's next segment is a stop's first,
  // and one draw of its noise moves the factor half-way.
  for (std::size_t i = 0; i < with.sigma_deg.size(); ++i) EXPECT_LE(with.sigma_deg[i], 1.05 * without.sigma_deg[i]);
  EXPECT_DOUBLE_EQ(with.sigma_deg.back(), without.sigma_deg.back());
  EXPECT_EQ(within_two_sigma(with), 8);
}

TEST(StopInnovations, AHeadingFixsOwnVarianceIsNotScaled) {
  EstimatorSettings settings;
  settings.automatic.scale_factor_sigma = 0.0;
  TwinRun twin(settings, 3);
  Estimator &calibrated = twin.calibrated, &plain = twin.plain;
  twin.run(30.0, 0.0, 0.0);
  for (int c = 0; c < 4; ++c) {  // stops that each find the bias 2 sigma from where it was
    twin.bias_shift_dps += 0.012;
    twin.run(60.0, 10.0, 0.5);
    twin.run(30.0, 0.0, 0.0);
  }
  ASSERT_GT(calibrated.last().heading_sigma_deg, 1.3 * plain.last().heading_sigma_deg);
  // A fix of 1 deg sigma: right after it the sigma shown is the filter's (the fix weighed
  // against the filter's own variance), not that times the stops' factor; what gathers after
  // it is scaled again.
  twin.fix(1.0);
  twin.run(1.0 / kHz, 0.0, 0.0);
  EXPECT_NEAR(calibrated.last().heading_sigma_deg, plain.last().heading_sigma_deg, 0.01);
  twin.run(60.0, 10.0, 0.5);
  EXPECT_GT(calibrated.last().heading_sigma_deg, plain.last().heading_sigma_deg + 0.01);
}

TEST(StopInnovations, ASegmentOnlyAStoppedHintMadeStillDoesNotCount) {
  // The wheels say "stopped" while the platform creeps at 0.1 dps (a wrong hint): the segments
  // are taken as still though their mean test fails. The first of them lies 0.1 dps from the
  // bias predicted, some fifteen sigma: counted as a stop's innovation, it alone would widen the
  // sigma for the rest of the run several times over. What the hint decided is not the filter's
  // claim, so the sigma shown after the next drive is the filter's own.
  EstimatorSettings settings;
  settings.automatic.scale_factor_sigma = 0.0;
  TwinRun twin(settings, 11);
  const Estimator &calibrated = twin.calibrated, &plain = twin.plain;
  twin.run(30.0, 0.0, 0.0);
  twin.run(60.0, 10.0, 0.5);
  twin.hint(MotionHint::Stopped);
  const auto accepted_before = plain.accepted_segments();
  twin.run(30.0, 0.1, 0.0);
  ASSERT_GE(plain.accepted_segments(), accepted_before + 8) << "the hint made the creep still";
  twin.hint(MotionHint::None);
  twin.run(60.0, 10.0, 0.5);
  ASSERT_EQ(calibrated.last().heading_deg, plain.last().heading_deg);
  // The start-up's first segment counts (it follows nothing accepted): a few percent at most.
  SCOPED_TRACE(std::to_string(calibrated.last().heading_sigma_deg) + " / " +
               std::to_string(plain.last().heading_sigma_deg));
  EXPECT_LE(calibrated.last().heading_sigma_deg, 1.05 * plain.last().heading_sigma_deg);
}

TEST(FixInnovations, ScalesTheGatheredVarianceByWhatTheFixesFoundWithTheStopsFactorAsThePrior) {
  FixInnovations f;
  EXPECT_DOUBLE_EQ(f.variance_scale(3.0, kFixScaleFloor), 3.0);  // no fix: the stops' factor
  // A fix 2 deg off where 1 deg^2 was gathered and nothing is unscaled: 4 / 1 = 4, weight 1;
  // with the prior of 1.5 weighed as kFixPriorWeight fixes.
  const double k = kFixPriorWeight;
  f.add(4.0, 1.0, 0.0);
  EXPECT_NEAR(f.variance_scale(1.5, kFixScaleFloor), (4.0 + k * 1.5) / (1.0 + k), 1e-12);
  // One where as much again was left unscaled weighs a quarter: its 8 of excess on 1 gathered.
  f.add(8.0, 1.0, 1.0);
  EXPECT_NEAR(f.variance_scale(1.5, kFixScaleFloor), (4.0 + 2.0 + k * 1.5) / (1.0 + 0.25 + k), 1e-12);
  // A hundred fixes that gathered a hundredth of what was unscaled, by turns on the heading and
  // twice the unscaled variance off (as they scatter): together they weigh a hundredth of one fix
  // (100 * 0.01^2 / 1.01^2) and leave the prior of 1 nearly as it was.
  FixInnovations soon;
  for (int i = 0; i < 100; ++i) soon.add(i % 2 == 0 ? -1.0 : 1.0, 0.01, 1.0);
  const double w = 0.01 / (1.01 * 1.01);
  EXPECT_NEAR(soon.variance_scale(1.0, kFixScaleFloor), k / (100 * w * 0.01 + k), 1e-9);
  EXPECT_GT(soon.variance_scale(1.0, kFixScaleFloor), 0.95);
  // Fixes that land on the heading: narrowed, but never below the floor.
  for (int i = 0; i < 50; ++i) f.add(-0.5, 1.0, 0.5);
  EXPECT_DOUBLE_EQ(f.variance_scale(1.5, kFixScaleFloor), kFixScaleFloor);
  f.add(std::nan(""), 1.0, 0.0);
  f.add(1.0, 0.0, 0.0);  // nothing gathered since the last fix: nothing to scale
  f.add(1.0, 1.0, -1.0);
  EXPECT_EQ(f.fixes(), 52u);
}

TEST(StopInnovations, FixesThatFindTheHeadingCloserThanTheSigmaSaidNarrowIt) {
  // The filter was told a bias walk 100 times the default's: its sigma grows over a drive many
  // times faster than the heading error does. The stops cannot narrow it (they see only the
  // bias); fixes from the truth at each drive's end see the heading well inside it and do.
  EstimatorSettings settings;
  settings.automatic.scale_factor_sigma = 0.0;
  settings.automatic.bias_walk_dps_rt_s = 1e-2;
  TwinRun twin(settings, 5);
  twin.run(30.0, 0.0, 0.0);
  int within = 0;
  double first_ratio = 0.0;
  for (int c = 0; c < 8; ++c) {
    twin.run(60.0, 10.0, 0.5);
    const double error = std::abs(std::remainder(twin.truth_deg - twin.calibrated.last().heading_deg, 360.0));
    within += error <= 2.0 * twin.calibrated.last().heading_sigma_deg;
    const double ratio = twin.calibrated.last().heading_sigma_deg / twin.plain.last().heading_sigma_deg;
    if (c == 0) first_ratio = ratio;
    SCOPED_TRACE("drive " + std::to_string(c) + ": error " + std::to_string(error) + ", sigma shown " +
                 std::to_string(twin.calibrated.last().heading_sigma_deg) + ", filter's own " +
                 std::to_string(twin.plain.last().heading_sigma_deg));
    if (c == 7) {
      EXPECT_LT(ratio, 0.7);
    }
    twin.fix(0.01);
    twin.run(30.0, 0.0, 0.0);
  }
  EXPECT_NEAR(first_ratio, 1.0, 0.05) << "before any fix, the filter's own (the stops do not narrow)";
  EXPECT_EQ(within, 8);
}

TEST(StopInnovations, AnExactFixOrOneFarOffIsNotCounted) {
  // An "exact" fix (variance 0) may set a frame (the dock is 0), and one far outside the sigma is
  // a wrong fix: neither says anything of the sigma's size. A fix near the heading, with its
  // variance, is counted.
  EstimatorSettings settings;
  settings.automatic.scale_factor_sigma = 0.0;
  TwinRun twin(settings, 9);
  const auto counted = [&] { return twin.calibrated.automatic()->fix_innovations().fixes(); };
  twin.run(30.0, 0.0, 0.0);
  twin.run(60.0, 10.0, 0.5);
  twin.calibrated.set_heading(0.0, 0.0);
  EXPECT_EQ(counted(), 0u);
  twin.run(60.0, 10.0, 0.5);
  twin.calibrated.set_heading(twin.calibrated.last().heading_deg + 90.0, 0.01);
  EXPECT_EQ(counted(), 0u);
  twin.run(60.0, 10.0, 0.5);
  twin.calibrated.set_heading(twin.calibrated.last().heading_deg + 0.2, 0.01);  // a fix within its sigma
  EXPECT_EQ(counted(), 1u);
}

TEST(StopInnovations, FrequentHonestFixesLeaveTheSigmaConsistent) {
  // A localisation system sending the heading at 1 Hz with an honest sigma of 0.1 deg: between
  // two fixes the filter gathers a tiny variance beside the 0.01 deg^2 the previous fix left, so
  // one fix's error says almost nothing of the gathered part's size, which is what the factor
  // scales once the fixes stop (a drive out of the map). Summed as if each fix told it, these
  // runs put the factor at 15, 2.1, 0.25 (the floor) and 0.25 although the filter's own sigma is
  // consistent (95-98 % of outputs within 2 sigma); weighed by what each can tell (240 of them
  // about as much as one fix after a long drive), at 3.8, 1.0, 0.63 and 0.89. The outputs between
  // 1 Hz fixes are within 2 sigma either way (the fix's own variance dominates them).
  EstimatorSettings settings;
  settings.automatic.scale_factor_sigma = 0.0;
  const std::pair<unsigned, unsigned> seeds[] = {{11u, 3u}, {11u, 111u}, {12u, 112u}, {13u, 113u}};
  for (const auto& [seed, fix_seed] : seeds) {
    TwinRun twin(settings, seed);
    std::mt19937_64 fix_rng(fix_seed);
    std::normal_distribution<double> fix_noise(0.0, 0.1);
    twin.run(30.0, 0.0, 0.0);
    int within = 0, outputs = 0, plain_within = 0;
    for (int c = 0; c < 4; ++c) {
      for (int s = 0; s < 60; ++s) {
        twin.run(1.0, 10.0, 0.5);
        const Estimate& e = twin.calibrated.last();
        within += std::abs(std::remainder(twin.truth_deg - e.heading_deg, 360.0)) <= 2.0 * e.heading_sigma_deg;
        const Estimate& p = twin.plain.last();
        plain_within += std::abs(std::remainder(twin.truth_deg - p.heading_deg, 360.0)) <= 2.0 * p.heading_sigma_deg;
        ++outputs;
        const double fix_deg = twin.truth_deg + fix_noise(fix_rng);
        twin.calibrated.set_heading(fix_deg, 0.01);
        twin.plain.set_heading(fix_deg, 0.01);
      }
      twin.run(30.0, 0.0, 0.0);
    }
    const auto* automatic = twin.calibrated.automatic();
    std::printf(
        "seeds %u/%u, 1 Hz fixes: factor %.3f on %llu fixes (the stops' %.3f); %d of %d outputs within 2 sigma "
        "(%d with the filter's own)\n",
        seed, fix_seed, automatic->heading_variance_scale(),
        static_cast<unsigned long long>(automatic->fix_innovations().fixes()), automatic->stop_variance_scale(), within,
        outputs, plain_within);
    EXPECT_EQ(automatic->fix_innovations().fixes(), 240u);
    EXPECT_GT(automatic->heading_variance_scale(), 0.4) << seed;
    EXPECT_LT(automatic->heading_variance_scale(), 5.0) << seed;
    EXPECT_GE(within, outputs * 85 / 100) << seed;
    EXPECT_LE(within, outputs * 995 / 1000) << seed;
  }
}
