#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/allan.hpp"

using namespace headingd::core;

namespace {

// Textbook overlapping Allan variance from cluster averages, for comparison.
double naive_adev(const std::vector<double>& x, double period_s, std::size_t m) {
  const std::size_t n = x.size();
  std::vector<double> averages;
  for (std::size_t k = 0; k + m <= n; ++k) {
    double sum = 0.0;
    for (std::size_t i = k; i < k + m; ++i) sum += x[i];
    averages.push_back(sum / static_cast<double>(m));
  }
  double sum = 0.0;
  std::size_t terms = 0;
  for (std::size_t k = 0; k + m < averages.size(); ++k, ++terms) {
    const double d = averages[k + m] - averages[k];
    sum += d * d;
  }
  (void)period_s;
  return std::sqrt(sum / (2.0 * static_cast<double>(terms)));
}

std::vector<double> white(std::size_t n, double sigma, unsigned seed, double offset = 0.0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<double> x(n);
  for (auto& v : x) v = offset + noise(rng);
  return x;
}

}  // namespace

TEST(Allan, MatchesNaiveImplementation) {
  const auto x = white(5000, 0.1, 1, -0.45);
  const auto clusters = log_spaced_clusters(x.size());
  const auto curve = allan_deviation(x, 0.0025, clusters);
  ASSERT_EQ(curve.size(), clusters.size());
  for (std::size_t i = 0; i < clusters.size(); ++i) {
    const double reference = naive_adev(x, 0.0025, clusters[i]);
    EXPECT_NEAR(curve[i].deviation, reference, 1e-9 * reference) << "m = " << clusters[i];
  }
}

TEST(Allan, RecoversWhiteNoiseDensityWithinThreePercent) {
  // Density N = 0.011 dps/sqrt(Hz) at 400 Hz: per-sample sigma N * sqrt(fs) = 0.22 dps.
  const double density = 0.011, fs = 400.0;
  const auto x = white(2'000'000, density * std::sqrt(fs), 7);
  const auto curve = allan_deviation(x, 1.0 / fs, log_spaced_clusters(x.size()));
  const auto terms = read_noise_terms(curve);
  EXPECT_NEAR(terms.arw, density, 0.03 * density);
  // Pure white noise: the deviation keeps falling with slope -1/2.
  EXPECT_NEAR(std::log(curve[20].deviation / curve[10].deviation) / std::log(curve[20].tau_s / curve[10].tau_s), -0.5,
              0.05);
}

TEST(Allan, RandomWalkShowsPlusHalfSlope) {
  // A rate random walk of density K: Allan deviation K sqrt(tau / 3).
  const double k = 1e-3, fs = 10.0;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> step(0.0, k / std::sqrt(fs));
  std::vector<double> x(200000);
  double walk = 0.0;
  for (auto& v : x) v = (walk += step(rng));
  const auto curve = allan_deviation(x, 1.0 / fs, log_spaced_clusters(x.size()));
  const auto terms = read_noise_terms(curve);
  ASSERT_TRUE(terms.rate_random_walk.has_value());
  EXPECT_NEAR(*terms.rate_random_walk, k, 0.3 * k);
}

TEST(Allan, ClusterSizesAreLogSpacedAndBounded) {
  const auto sizes = log_spaced_clusters(1000, 10, 9);
  ASSERT_FALSE(sizes.empty());
  EXPECT_EQ(sizes.front(), 1u);
  EXPECT_LE(2 * sizes.back() + 8, 1000u);
  for (std::size_t i = 1; i < sizes.size(); ++i) EXPECT_GT(sizes[i], sizes[i - 1]);
  EXPECT_TRUE(log_spaced_clusters(5).empty());
}
