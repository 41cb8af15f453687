// The floor (tools/heading_floor) on a recording written here by hand, not by our simulator:
// a gyro with a known bias that drifts, still, then a 90 degree turn at 15 dps that starts and
// ends between the truth's 10 Hz rows, still again. Without noise the floor is the truth.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "temp_dir.hpp"
#include "tools/heading_floor.hpp"

using headingd::test::TempDir;

namespace {

constexpr double kRateHz = 200.0;
constexpr double kTurnStartS = 20.037;  // between samples' truth rows on purpose
constexpr double kTurnDps = 15.0;
constexpr double kTurnS = 6.0;

double true_bias(double t) { return 0.4 + 0.002 * t; }
double true_rate(double t) { return t >= kTurnStartS && t < kTurnStartS + kTurnS ? kTurnDps : 0.0; }
double true_heading(double t) { return kTurnDps * std::clamp(t - kTurnStartS, 0.0, kTurnS); }

}  // namespace

TEST(HeadingFloor, WithoutNoiseTheFloorIsTheTruth) {
  TempDir dir;
  std::string imu = "time_s,gx_dps,gy_dps,gz_dps,temp_c\n";
  std::string truth = "time_s,heading_deg,bias_z_dps,moving\n";
  char line[160];
  const int samples = static_cast<int>(60.0 * kRateHz);
  for (int i = 0; i < samples; ++i) {
    const double t = i / kRateHz;
    // The mean rate over the interval ending at this sample, as a gyro's filtered output gives it.
    const double rate = i == 0 ? 0.0 : (true_heading(t) - true_heading(t - 1.0 / kRateHz)) * kRateHz;
    std::snprintf(line, sizeof line, "%.6f,0.1,-0.2,%.12f,25\n", t, rate + true_bias(t));
    imu += line;
    if (i % 20 == 0) {
      const bool moving = true_rate(t) != 0.0;
      std::snprintf(line, sizeof line, "%.6f,%.9f,%.12f,%d\n", t, true_heading(t), true_bias(t), moving ? 1 : 0);
      truth += line;
    }
  }
  const auto truth_data = headingd::app::read_truth(dir.file("truth.csv", truth));
  const auto floor = headingd::app::floor_heading(dir.file("imu.csv", imu), truth_data);
  ASSERT_GT(floor.t_s.size(), 590u);
  double worst = 0.0;
  for (std::size_t i = 0; i < floor.t_s.size(); ++i)
    worst = std::max(worst, std::abs(floor.value[i] - true_heading(floor.t_s[i])));
  EXPECT_LT(worst, 1e-6);
  // Scored as an estimate against the truth it is exact; an estimate that ends 2 degrees off
  // has an excess of 2 degrees over it.
  const auto floor_metrics = headingd::app::score_heading(floor, truth_data.heading);
  EXPECT_LT(floor_metrics.max_abs_deg(), 1e-6);
  headingd::app::TimeSeries off = floor;
  for (double& v : off.value) v += 2.0;
  EXPECT_NEAR(headingd::app::score_heading(off, floor).max_abs_deg(), 2.0, 1e-9);
}
