// The heading sigma calibrated by the run's own stops (core/stop_innovations.hpp): the part
// on its own, then method auto on crafted runs whose bias moves more, or less, between stops
// than the filter was told.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
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
  EstimatorSettings filter_only = settings;
  filter_only.automatic.calibrate_sigma = false;
  Estimator calibrated(settings), plain(filter_only);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  long index = 0;
  double bias_z = -0.45;
  const auto run = [&](double seconds, double rate_dps, double shake_dps) {
    for (long i = 0; i < std::lround(seconds * kHz); ++i) {
      Sample s;
      s.t_s = static_cast<double>(index++) / kHz;
      const double shake = shake_dps * noise(rng);
      s.rate_dps = Vec3(0.3 + 0.05 * noise(rng) + shake, -0.2 + 0.05 * noise(rng) + shake,
                        bias_z + rate_dps + 0.2 * noise(rng) + 0.3 * shake);
      calibrated.update(s);
      plain.update(s);
    }
  };
  run(30.0, 0.0, 0.0);
  for (int c = 0; c < 4; ++c) {  // stops that each find the bias 2 sigma from where it was
    bias_z += 0.012;
    run(60.0, 10.0, 0.5);
    run(30.0, 0.0, 0.0);
  }
  ASSERT_GT(calibrated.last().heading_sigma_deg, 1.3 * plain.last().heading_sigma_deg);
  // A fix of 1 deg sigma: right after it the sigma shown is the filter's (the fix weighed
  // against the filter's own variance), not that times the stops' factor; what gathers after
  // it is scaled again.
  calibrated.set_heading(0.0, 1.0);
  plain.set_heading(0.0, 1.0);
  run(0.1, 0.0, 0.0);
  EXPECT_NEAR(calibrated.last().heading_sigma_deg, plain.last().heading_sigma_deg, 0.01);
  run(60.0, 10.0, 0.5);
  EXPECT_GT(calibrated.last().heading_sigma_deg, plain.last().heading_sigma_deg + 0.01);
}
