#pragma once
// Heading error against an orientation truth (motion capture: time_s,qw,qx,qy,qz[,moving], as the
// BROAD recordings carry it, "nan" where tracking was lost; or EuRoC/ASL ground truth, "#timestamp
// [ns],…,q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z [],…"), defined as BROAD's README defines it:
// the rotation angle about the earth's vertical of q_true * q_est^-1, the estimate aligned to the
// truth at the first instant both have. The estimates' own attitude is what is scored, so a tilt
// integrated wrongly shows as the heading error it causes.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "core/heading_metrics.hpp"

namespace headingd::app {

// The twist about the earth's z axis (deg, in [-180, 180]) of truth * estimate^-1.
double heading_twist_deg(const Eigen::Quaterniond& truth, const Eigen::Quaterniond& estimate);

struct OrientationScore {
  core::HeadingMetrics all, moving;  // `moving`: the rows the truth marks as moving
  bool has_moving = false;           // the truth has a `moving` column
  std::uint64_t within_2sigma = 0, moving_within_2sigma = 0;
  bool has_sigma = true;                          // every scored row carried a finite heading sigma
  std::vector<std::pair<double, double>> errors;  // (t_s, error_deg) at each scored row
  // EuRoC/ASL ground truth carries the gyro bias too (b_w_RS_S_*, rad/s, in the sensor's axes
  // as ours): estimate minus truth at each scored row, per axis, in deg/s.
  bool has_bias = false;
  std::uint64_t bias_rows = 0;
  Eigen::Vector3d bias_sum_sq_dps2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d bias_last_error_dps = Eigen::Vector3d::Zero();
};

// True when the file's header names time_s, qw, qx, qy and qz, or EuRoC's timestamp and q_RS_*. Throws
// drivers::InputError/OpenError.
bool is_orientation_truth(const std::string& truth_path);

// Scores the estimates (time_s,qw,qx,qy,qz,heading_sigma_deg; bias_*_dps against a truth's bias) at each of their rows
// inside the truth's span, the truth interpolated (slerp) between its two rows around it when both are valid and at
// most `max_truth_gap_s` apart; other rows are skipped. Throws drivers::InputError/OpenError.
OrientationScore score_orientation(const std::string& estimates_path, const std::string& truth_path,
                                   double max_truth_gap_s = 0.1);

}  // namespace headingd::app
