// Published stamps against a wall clock that steps while the daemon runs (an injected clock;
// the real one is not ours to step in a test): a sensor at 400 Hz read in bursts of 16, each
// sample handled up to a burst after it was taken.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "pipeline/wall_stamps.hpp"

using headingd::pipeline::kSlewDownPerS;
using headingd::pipeline::WallStamps;

namespace {

constexpr double kEpoch = 1.7e9;  // wall time at monotonic 0
constexpr double kRateHz = 400.0;
constexpr int kBurst = 16;

struct StampRun {
  std::vector<double> t, stamp, true_wall;
};

// 200 s of samples; the wall clock steps by `step_s` at t = 30 s.
StampRun run_with_step(double step_s) {
  double wall_now = 0.0;
  WallStamps stamps([&] { return wall_now; });
  StampRun run;
  const auto true_wall = [&](double t) { return kEpoch + t + (t >= 30.0 ? step_s : 0.0); };
  for (int i = 0; i < static_cast<int>(200 * kRateHz); i += kBurst) {
    const double handled_t = (i + kBurst - 1) / kRateHz + 0.002;  // the burst is read 2 ms after its last sample
    for (int k = i; k < i + kBurst; ++k) {
      const double t = k / kRateHz;
      wall_now = true_wall(handled_t);
      run.t.push_back(t);
      run.stamp.push_back(stamps.stamp(t));
      run.true_wall.push_back(true_wall(t));
    }
  }
  return run;
}

double error_at(const StampRun& run, double t) {
  const auto i = static_cast<std::size_t>(t * kRateHz);
  return run.stamp[i] - run.true_wall[i];
}

void expect_increasing(const StampRun& run) {
  for (std::size_t i = 1; i < run.stamp.size(); ++i)
    ASSERT_GT(run.stamp[i], run.stamp[i - 1]) << "stamp went backwards at t = " << run.t[i];
}

}  // namespace

TEST(WallStamps, FollowsAForwardStepWithinOneSecond) {
  const StampRun run = run_with_step(+10.0);
  expect_increasing(run);
  EXPECT_LT(std::abs(error_at(run, 29.0)), 0.05) << "before the step";
  for (int k = 0; 31.0 + 0.25 * k < 200.0; ++k) {
    const double t = 31.0 + 0.25 * k;
    EXPECT_LT(std::abs(error_at(run, t)), 0.05) << "at t = " << t;
  }
  EXPECT_EQ(run.stamp.size(), static_cast<std::size_t>(200 * kRateHz)) << "every sample stamped once";
}

TEST(WallStamps, ABackwardStepNeverGoesBackAndConvergesAtTheSlewRate) {
  const StampRun run = run_with_step(-10.0);
  expect_increasing(run);
  // 50 s into the slew the stamps are 10 - 50 * rate ahead of the new clock, and caught up
  // after 10 / rate s.
  EXPECT_NEAR(error_at(run, 80.0), 10.0 - 50.0 * kSlewDownPerS, 0.1);
  const double caught_up_t = 30.0 + 10.0 / kSlewDownPerS + 1.0;
  for (int k = 0; caught_up_t + 0.25 * k < 200.0; ++k) {
    const double t = caught_up_t + 0.25 * k;
    EXPECT_LT(std::abs(error_at(run, t)), 0.05) << "at t = " << t;
  }
  EXPECT_EQ(run.stamp.size(), static_cast<std::size_t>(200 * kRateHz)) << "every sample stamped once";
}

TEST(WallStamps, WithoutStepsTheStampIsTheSampleTimeOnTheWallClock) {
  const StampRun run = run_with_step(0.0);
  expect_increasing(run);
  for (int k = 0; 1.0 + 0.25 * k < 200.0; ++k) {
    const double t = 1.0 + 0.25 * k;
    EXPECT_LT(std::abs(error_at(run, t)), 0.05) << "at t = " << t;
  }
}
