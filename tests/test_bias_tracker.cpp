#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/bias_tracker.hpp"

using namespace headingd::core;

namespace {

constexpr double kRateHz = 400.0;
constexpr double kNoise = 0.1;

// Feeds `seconds` of a still-or-turning z signal into the tracker.
class Signal {
 public:
  explicit Signal(BiasTracker& tracker) : tracker_(tracker) {}
  void run(double seconds, double bias_z, double true_rate_z) {
    const auto n = static_cast<int>(std::lround(seconds * kRateHz));
    for (int i = 0; i < n; ++i) {
      Sample s;
      s.t_s = static_cast<double>(index_++) / kRateHz;
      s.rate_dps = Vec3(0.2 + noise_(rng_), -0.1 + noise_(rng_), bias_z + true_rate_z + noise_(rng_));
      tracker_.update(s);
    }
  }

 private:
  BiasTracker& tracker_;
  std::mt19937_64 rng_{11};
  std::normal_distribution<double> noise_{0.0, kNoise};
  long index_ = 0;
};

BiasTracker tracker_for(Method method) { return BiasTracker(method, BiasSettings{}); }

// Mean of 1200 samples with sigma 0.1: standard error 0.003 dps.
constexpr double kTol = 0.015;

}  // namespace

TEST(BiasTracker, StartupSegmentGivesBiasAndSigma) {
  auto tracker = tracker_for(Method::A);
  Signal signal(tracker);
  signal.run(3.1, -0.40, 0.0);
  EXPECT_FALSE(tracker.in_startup());
  EXPECT_NEAR(tracker.bias_dps().z(), -0.40, kTol);
  EXPECT_NEAR(tracker.bias_dps().x(), 0.2, kTol);
  EXPECT_NEAR(tracker.sigma_still_dps().z(), kNoise, 0.01);
  EXPECT_EQ(tracker.accepted_segments(), 1u);
}

TEST(BiasTracker, MethodsOnBiasStepTurnAndCreep) {
  auto a = tracker_for(Method::A);
  auto b = tracker_for(Method::B);
  auto c = tracker_for(Method::C);
  Signal sa(a), sb(b), sc(c);
  auto run = [&](double seconds, double bias, double rate) {
    sa.run(seconds, bias, rate);
    sb.run(seconds, bias, rate);
    sc.run(seconds, bias, rate);
  };

  run(30.0, -0.40, 0.0);
  run(15.0, -0.35, 0.0);  // bias step of half a sigma: B and C follow, A keeps its start value
  EXPECT_NEAR(a.bias_dps().z(), -0.40, kTol);
  EXPECT_NEAR(b.bias_dps().z(), -0.35, kTol);
  EXPECT_NEAR(c.bias_dps().z(), -0.35, kTol);

  run(3.0, -0.35, 20.0);  // a fast turn: everyone rejects it by range
  EXPECT_NEAR(b.bias_dps().z(), -0.35, kTol);
  EXPECT_NEAR(c.bias_dps().z(), -0.35, kTol);

  const auto c_rejected = c.rejected_segments();
  run(30.0, -0.35, 0.3);  // slow creep: B absorbs it into the bias, C's mean test refuses it
  EXPECT_NEAR(b.bias_dps().z(), -0.05, kTol);
  EXPECT_NEAR(c.bias_dps().z(), -0.35, kTol);
  EXPECT_GE(c.rejected_segments(), c_rejected + 2);
  EXPECT_NEAR(a.bias_dps().z(), -0.40, kTol);
  EXPECT_EQ(a.accepted_segments(), 1u);
}

TEST(BiasTracker, VerdictReportedOnTheClosingSample) {
  auto tracker = tracker_for(Method::C);
  Sample s;
  SegmentVerdict verdict;
  int closes = 0;
  for (int i = 0; i <= 2400; ++i) {
    s.t_s = i / kRateHz;
    verdict = tracker.update(s);
    if (verdict.closed) {
      ++closes;
      EXPECT_EQ(i % 1200, 0) << "segments are exactly 3 s at 400 Hz";
    }
  }
  EXPECT_EQ(closes, 2);
  EXPECT_TRUE(verdict.accepted);  // a constant signal is still
}

TEST(BiasTracker, SetBiasRestoresAndSeedsHistory) {
  BiasSettings settings;
  settings.still_at_start = false;
  settings.sigma_still_dps = Vec3(kNoise, kNoise, kNoise);
  BiasTracker tracker(Method::C, settings);
  tracker.set_bias(Vec3(0.2, -0.1, -0.40));
  EXPECT_FALSE(tracker.in_startup());
  EXPECT_EQ(tracker.bias_dps(), Vec3(0.2, -0.1, -0.40));
  Signal signal(tracker);
  signal.run(3.5, -0.10, 0.0);  // a mean far from the restored bias is refused by criterion 3
  EXPECT_EQ(tracker.accepted_segments(), 0u);
  EXPECT_NEAR(tracker.bias_dps().z(), -0.40, 1e-12);
}

TEST(BiasSettings, ValidationNamesTheField) {
  BiasSettings s;
  s.segment_s = 0.0;
  ASSERT_TRUE(validate(s).has_value());
  EXPECT_NE(validate(s)->find("segment_s"), std::string::npos);
  s = BiasSettings{};
  s.still_at_start = false;
  EXPECT_NE(validate(s)->find("sigma_still_dps"), std::string::npos);
  EXPECT_FALSE(validate(BiasSettings{}).has_value());
}
