// `headingd score` against an orientation truth (tools/orientation_score), on files written here
// by hand, not by our simulator: a sensor tilted 20 degrees that turns 100 degrees about the
// vertical, a motion-capture truth at 100 Hz that loses track for half a second, estimates at
// 10 Hz between the truth's rows, in a frame of their own, whose heading error grows to 2 degrees.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <string>

#include "temp_dir.hpp"
#include "tools/orientation_score.hpp"

using headingd::test::TempDir;
using Quat = Eigen::Quaterniond;

namespace {

constexpr double kPi = 3.14159265358979323846;
double rad(double deg) { return deg * kPi / 180.0; }
Quat about_z(double deg) { return Quat(Eigen::AngleAxisd(rad(deg), Eigen::Vector3d::UnitZ())); }
Quat about_x(double deg) { return Quat(Eigen::AngleAxisd(rad(deg), Eigen::Vector3d::UnitX())); }

bool moving(double t) { return t >= 5.0 && t < 15.0; }
double yaw(double t) { return 10.0 * std::clamp(t - 5.0, 0.0, 10.0); }
double error(double t) { return 0.2 * std::clamp(t - 5.0, 0.0, 10.0); }
bool tracking_lost(double t) { return t >= 8.0 && t < 8.5; }

std::string row(double t, const Quat& q, const char* tail) {
  char text[200];
  std::snprintf(text, sizeof text, "%.6f,%.12f,%.12f,%.12f,%.12f%s\n", t, q.w(), q.x(), q.y(), q.z(), tail);
  return text;
}

}  // namespace

TEST(OrientationScore, TheTwistAboutTheVerticalWrapsAndIgnoresACommonTilt) {
  using headingd::app::heading_twist_deg;
  EXPECT_NEAR(heading_twist_deg(about_z(30) * about_x(40), about_z(10) * about_x(40)), 20.0, 1e-9);
  EXPECT_NEAR(heading_twist_deg(about_z(-170), about_z(170)), 20.0, 1e-9);
  EXPECT_NEAR(heading_twist_deg(about_z(170), about_z(-170)), -20.0, 1e-9);
}

TEST(OrientationScore, ScoresTheTurnAgainstAMotionCaptureTruth) {
  TempDir dir;
  std::string truth = "time_s,qw,qx,qy,qz,moving\n";
  for (int i = 0; i <= 2000; ++i) {
    const double t = i / 100.0;
    if (tracking_lost(t)) {
      char text[80];
      std::snprintf(text, sizeof text, "%.6f,nan,nan,nan,nan,1\n", t);
      truth += text;
      continue;
    }
    truth += row(t, about_z(yaw(t)) * about_x(20), moving(t) ? ",1" : ",0");
  }
  // The estimates' own frame differs from the truth's by `frame`; the score aligns them at the start.
  const Quat frame = about_z(75) * about_x(-30);
  std::string estimates = "time_s,heading_deg,qw,qx,qy,qz,bias_x_dps,bias_y_dps,bias_z_dps,heading_sigma_deg,still\n";
  for (int i = 0; i < 200; ++i) {
    const double t = 0.005 + i / 10.0;
    const Quat q = frame.inverse() * about_z(yaw(t) - error(t)) * about_x(20);
    char text[240];
    std::snprintf(text, sizeof text, "%.6f,0,%.12f,%.12f,%.12f,%.12f,0,0,0,0.75,0\n", t, q.w(), q.x(), q.y(), q.z());
    estimates += text;
  }
  const std::string truth_path = dir.file("truth.csv", truth);
  ASSERT_TRUE(headingd::app::is_orientation_truth(truth_path));
  EXPECT_FALSE(headingd::app::is_orientation_truth(dir.file("heading.csv", "time_s,heading_deg,bias_z_dps,moving\n")));
  const auto score = headingd::app::score_orientation(dir.file("est.csv", estimates), truth_path);

  // Every estimate row is scored but the five whose truth neighbours were lost.
  EXPECT_EQ(score.all.count(), 200u - 5u);
  ASSERT_EQ(score.errors.size(), score.all.count());
  double worst = 0.0;
  for (const auto& [t, e] : score.errors) {
    EXPECT_FALSE(tracking_lost(t)) << t;
    worst = std::max(worst, std::abs(e - error(t)));
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_NEAR(score.all.max_abs_deg(), 2.0, 1e-6);
  EXPECT_NEAR(score.all.final_abs_deg(), 2.0, 1e-6);
  // Moving: 5.005 .. 14.905 s less the five lost, the error within 2 x 0.75 up to 12.5 s.
  ASSERT_TRUE(score.has_moving);
  EXPECT_EQ(score.moving.count(), 100u - 5u);
  EXPECT_NEAR(score.moving.max_abs_deg(), error(14.905), 1e-6);
  EXPECT_EQ(score.moving_within_2sigma, 75u - 5u);
  EXPECT_TRUE(score.has_sigma);
}
