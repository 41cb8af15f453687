#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/segment_stats.hpp"

using headingd::core::SegmentStats;
using headingd::core::Vec3;

namespace {

struct Naive {
  Vec3 mean, sigma, min, max;
};

// Two passes over stored samples: the textbook definitions the streaming code must match.
Naive naive(const std::vector<Vec3>& xs) {
  Naive n;
  n.mean = Vec3::Zero();
  for (const auto& x : xs) n.mean += x;
  n.mean /= static_cast<double>(xs.size());
  Vec3 ss = Vec3::Zero();
  for (const auto& x : xs) ss += (x - n.mean).cwiseAbs2();
  n.sigma = (ss / static_cast<double>(xs.size() - 1)).cwiseSqrt();
  n.min = n.max = xs.front();
  for (const auto& x : xs) {
    n.min = n.min.cwiseMin(x);
    n.max = n.max.cwiseMax(x);
  }
  return n;
}

}  // namespace

TEST(SegmentStats, MatchesTwoPassComputationWithLargeOffset) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 0.1);
  // A large bias next to small noise is where a naive one-pass sum-of-squares loses digits.
  const Vec3 offset(1000.0, -250.0, 0.455);
  std::vector<Vec3> xs;
  SegmentStats stats;
  for (int i = 0; i < 1200; ++i) {
    const Vec3 x = offset + Vec3(noise(rng), 3 * noise(rng), noise(rng));
    xs.push_back(x);
    stats.add(x);
  }
  const Naive expected = naive(xs);
  EXPECT_EQ(stats.count(), 1200u);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(stats.mean_dps()[a], expected.mean[a], 1e-10);
    EXPECT_NEAR(stats.sigma_dps()[a], expected.sigma[a], 1e-9);
    EXPECT_EQ(stats.min_dps()[a], expected.min[a]);
    EXPECT_EQ(stats.max_dps()[a], expected.max[a]);
    EXPECT_DOUBLE_EQ(stats.range_dps()[a], expected.max[a] - expected.min[a]);
  }
}

TEST(SegmentStats, ResetForgetsEverything) {
  SegmentStats stats;
  stats.add(Vec3(5, 5, 5));
  stats.add(Vec3(-5, -5, -5));
  stats.reset();
  stats.add(Vec3(1, 2, 3));
  EXPECT_EQ(stats.count(), 1u);
  EXPECT_EQ(stats.mean_dps(), Vec3(1, 2, 3));
  EXPECT_EQ(stats.range_dps(), Vec3::Zero());
  EXPECT_EQ(stats.sigma_dps(), Vec3::Zero());
}
