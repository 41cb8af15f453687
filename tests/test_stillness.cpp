#include <gtest/gtest.h>

#include <random>

#include "core/stillness.hpp"

using namespace headingd::core;

namespace {

constexpr double kRateHz = 400.0;
constexpr double kSigma = 0.1;  // dps, per-sample noise of a still sensor

// A 3 s segment: noise of kSigma around `bias`, plus a true rate ramping from `rate_start`
// to `rate_end` on z.
SegmentStats segment(double bias, double rate_start, double rate_end, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, kSigma);
  SegmentStats stats;
  const int n = static_cast<int>(3.0 * kRateHz);
  for (int i = 0; i < n; ++i) {
    const double rate = rate_start + (rate_end - rate_start) * i / (n - 1);
    stats.add(Vec3(noise(rng), noise(rng), bias + rate + noise(rng)));
  }
  return stats;
}

const Vec3 kSigmaStill(kSigma, kSigma, kSigma);

}  // namespace

TEST(RangeCriterion, AcceptsStillSegment) {
  int accepted = 0;
  for (unsigned seed = 0; seed < 50; ++seed) accepted += range_says_still(segment(-0.45, 0, 0, seed), kSigmaStill, 7.0);
  // The range of 1200 Gaussian samples is about 6.5 sigma, so k_R = 7 passes about 80 % of
  // still segments per axis, and about half when all three axes must pass.
  EXPECT_GE(accepted, 15);
  EXPECT_LE(accepted, 40);
}

TEST(RangeCriterion, RejectsFastTurn) {
  EXPECT_FALSE(range_says_still(segment(-0.45, 0.0, 10.0, 1), kSigmaStill, 7.0));
  EXPECT_FALSE(range_says_still(segment(-0.45, 5.0, 5.0, 1) /* constant 5 dps */, kSigmaStill, 0.1));
}

TEST(RangeCriterion, MissesSlowDriftThatMeanTestCatches) {
  // A constant 0.3 dps creep does not widen the range: the paper's weakness.
  const SegmentStats creep = segment(-0.45, 0.3, 0.3, 2);
  EXPECT_TRUE(range_says_still(creep, Vec3(kSigma, kSigma, 2 * kSigma), 7.0));
  MeanHistory history(10);
  history.push(Vec3(0, 0, -0.45));
  EXPECT_FALSE(history.consistent(creep.mean_dps(), kSigmaStill, 1.0));
  EXPECT_TRUE(history.consistent(segment(-0.45, 0, 0, 3).mean_dps(), kSigmaStill, 1.0));
}

TEST(RangeCriterion, RejectsSegmentWithFewerThanTwoSamples) {
  SegmentStats one;
  one.add(Vec3::Zero());
  EXPECT_FALSE(range_says_still(one, kSigmaStill, 7.0));
}

TEST(MeanHistory, MovingAverageOfLastN) {
  MeanHistory history(3);
  EXPECT_TRUE(history.consistent(Vec3(100, 100, 100), kSigmaStill, 1.0));  // empty: nothing to disagree with
  for (double v : {1.0, 2.0, 3.0, 4.0, 5.0}) history.push(Vec3(v, v, v));
  EXPECT_EQ(history.size(), 3u);
  EXPECT_NEAR(history.moving_average_dps().z(), 4.0, 1e-12);  // (3 + 4 + 5) / 3
  EXPECT_TRUE(history.consistent(Vec3(4.05, 4.0, 3.95), kSigmaStill, 1.0));
  EXPECT_FALSE(history.consistent(Vec3(4.0, 4.0, 4.2), kSigmaStill, 1.0));
}
