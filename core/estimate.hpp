#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>

#include "core/sample.hpp"

namespace headingd::core {

struct SegmentVerdict {
  bool closed = false;  // this sample closed a segment; the fields below describe it
  std::uint64_t index = 0;
  bool range_ok = false;
  bool mean_ok = false;
  bool accepted = false;  // the segment was taken as still and its mean as a bias measurement
};

// What every estimator reports after each sample.
struct Estimate {
  double t_s = 0.0;
  double heading_deg = 0.0;  // unwrapped integral of the bias-corrected z rate
  Eigen::Quaterniond attitude = Eigen::Quaterniond::Identity();
  Vec3 bias_dps = Vec3::Zero();
  Vec3 bias_sigma_dps = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  Vec3 rate_dps = Vec3::Zero();                                         // bias-corrected
  double heading_sigma_deg = std::numeric_limits<double>::quiet_NaN();  // NaN: not provided
  double temp_c = std::numeric_limits<double>::quiet_NaN();             // the sample's; NaN when none
  bool in_startup = false;  // heading held while the start-up segment is measured
  // The estimator's state went non-finite (past every input check): the heading stays at its
  // last finite value with an infinite sigma for the rest of the run. Never NaN with sigma 0.
  bool fault = false;
  std::uint64_t segment_index = 0;  // segment this sample belongs to
  SegmentVerdict closed;            // the segment this sample closed, if any
};

// Hints from the vehicle controller (HeadingCommand): wheels stopped or driving.
enum class MotionHint { None, Stopped, Moving };

}  // namespace headingd::core
