// A gap in the samples (a lost FIFO, a chip set up again after bus errors, a recording's hole):
// `auto` bridges it at the rate on either side, with the doubt the two leave in the sigma, and
// takes nothing unseen for a stop. Before, the one sample after a gap stood for all of it.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/estimator.hpp"

using namespace headingd::core;

namespace {

constexpr double kRateHz = 400.0;

// A level platform: true z rate on top of a bias of -0.45 dps and white noise (0.2 dps per
// sample on z, 1 dps on x and y: a sample's noise held over a gap shows on every axis).
class Platform {
 public:
  // `seconds` of samples at a true z rate.
  void run(double seconds, double rate_dps) {
    const auto n = static_cast<long>(std::lround(seconds * kRateHz));
    for (long i = 0; i < n; ++i) {
      Sample s;
      s.t_s = static_cast<double>(index_++) / kRateHz;
      s.temp_c = 30.0;
      s.rate_dps = Vec3(0.3 + noise_(rng_), -0.2 + noise_(rng_), -0.45 + rate_dps + 0.2 * noise_(rng_));
      if (index_ > 1) true_heading_ += rate_dps / kRateHz;
      estimator_.update(s);
    }
  }
  // `seconds` with no samples, over which the platform turned by `turn_deg`.
  void gap(double seconds, double turn_deg) {
    index_ += std::lround(seconds * kRateHz);
    true_heading_ += turn_deg;
  }
  const Estimator& estimator() const { return estimator_; }
  double error_deg() const { return estimator_.last().heading_deg - true_heading_; }
  double sigma_deg() const { return estimator_.last().heading_sigma_deg; }
  // The attitude's tilt from level, deg (the platform never tilts).
  double tilt_deg() const {
    const Vec3 up = estimator_.last().attitude * Vec3::UnitZ();
    return std::acos(std::min(1.0, up.z())) * 180.0 / 3.14159265358979;
  }

 private:
  Estimator estimator_;
  std::mt19937_64 rng_{7};
  std::normal_distribution<double> noise_{0.0, 1.0};
  long index_ = 0;
  double true_heading_ = 0.0;
};

}  // namespace

TEST(SampleGaps, AGapInAStopLeavesHeadingAndAttitudeWhereTheyWere) {
  Platform p;
  p.run(60.0, 0.0);
  p.gap(30.0, 0.0);
  p.run(60.0, 0.0);
  EXPECT_EQ(p.estimator().diagnostics().gaps_bridged, 1u);
  EXPECT_NEAR(p.estimator().diagnostics().gaps_bridged_s, 30.0, 0.01);
  // One sample held over 30 s would be off by its noise times 30 s: 6 deg on z, 30 deg of tilt.
  EXPECT_LT(std::abs(p.error_deg()), 0.1);
  EXPECT_LT(p.tilt_deg(), 0.5);
  EXPECT_LT(p.sigma_deg(), 0.5) << "a stop on both sides: nothing to doubt";
}

TEST(SampleGaps, AnHourUnseenInAStopKeepsTheStopsSigma) {
  // A suspend, a recorder paused: the angle is held as over a stop, and the bias walk over the
  // hour goes into the bias's variance, not into the heading's.
  Platform p;
  p.run(60.0, 0.0);
  const double sigma_before = p.sigma_deg();
  p.gap(3600.0, 0.0);
  p.run(1.0, 0.0);
  EXPECT_LT(std::abs(p.error_deg()), 0.1);
  EXPECT_LT(p.sigma_deg(), sigma_before + 0.05);
  EXPECT_GT(p.estimator().last().bias_sigma_dps.z(), 0.005) << "the bias may have walked meanwhile";
  p.run(60.0, 0.0);
  EXPECT_LT(std::abs(p.error_deg()), 0.1) << "and the next stop's bias does not move the held heading";
}

TEST(SampleGaps, ATurnThatGoesOnThroughAGapIsIntegratedAtItsRate) {
  Platform p;
  p.run(30.0, 0.0);
  p.run(10.0, 20.0);
  p.gap(2.0, 40.0);
  p.run(5.0, 20.0);
  p.run(30.0, 0.0);
  EXPECT_LT(std::abs(p.error_deg()), 1.0);
  EXPECT_LE(std::abs(p.error_deg()), 2.0 * p.sigma_deg());
}

TEST(SampleGaps, ATurnThatEndsInAGapIsHalvedAndDoubted) {
  Platform p;
  p.run(30.0, 0.0);
  p.run(10.0, 20.0);
  p.gap(2.0, 10.0);  // 20 dps for half a second, then still: 10 deg where halfway says 20
  p.run(30.0, 0.0);
  const double error = p.error_deg(), sigma = p.sigma_deg();
  std::printf("turn ending in a gap: error %.2f deg, sigma %.2f deg\n", error, sigma);
  EXPECT_NEAR(error, 10.0, 1.0) << "the turn taken halfway between the rates on either side";
  EXPECT_LE(std::abs(error), 2.0 * sigma) << "and the sigma says it may be off by that";
  EXPECT_LT(sigma, 30.0) << "but not by more than the whole gap at the faster rate";
}

TEST(SampleGaps, NothingUnseenIsTakenForAStop) {
  // A segment under way when the gap came is judged on what it had; the one after the gap
  // starts with the sample after it. Ten gaps in a stop: the bias stays where the stop put it.
  Platform p;
  p.run(30.0, 0.0);
  for (int i = 0; i < 10; ++i) {
    p.run(1.3, 0.0);
    p.gap(0.5, 0.0);
  }
  p.run(30.0, 0.0);
  const Diagnostics d = p.estimator().diagnostics();
  EXPECT_EQ(d.gaps_bridged, 10u);
  EXPECT_NEAR(p.estimator().last().bias_dps.z(), -0.45, 0.01);
  EXPECT_LT(std::abs(p.error_deg()), 0.1);
}

TEST(SampleGaps, ADelayedSampleIsNoGap) {
  // Lost samples within four intervals (a few at 400 Hz), or within 0.1 s (an overrun's FIFO
  // or two), are ordinary intervals.
  Platform p;
  p.run(30.0, 0.0);
  for (int i = 0; i < 100; ++i) {
    p.run(0.5, 0.0);
    p.gap(3.0 / kRateHz, 0.0);
    p.run(0.5, 0.0);
    p.gap(0.09, 0.0);
  }
  EXPECT_EQ(p.estimator().diagnostics().gaps_bridged, 0u);
}

TEST(SampleGaps, AGapInTheStartUpEndsItThere) {
  // Shorter than a segment's minimum, the held start-up is dropped and starts again after the
  // gap; longer, it is judged on what it has. Either way the first stop measures the bias.
  for (const double before_s : {0.5, 2.0}) {
    Platform p;
    p.run(before_s, 0.0);
    p.gap(10.0, 0.0);
    p.run(60.0, 0.0);
    EXPECT_EQ(p.estimator().diagnostics().gaps_bridged, 1u) << before_s;
    EXPECT_FALSE(p.estimator().in_startup()) << before_s;
    EXPECT_NEAR(p.estimator().last().bias_dps.z(), -0.45, 0.01) << before_s;
    EXPECT_LT(std::abs(p.error_deg()), 0.1) << before_s;
  }
}
