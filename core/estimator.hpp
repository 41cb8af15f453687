#pragma once
// One sample in, one estimate out: the bias tracker plus heading and attitude integration.
#include <cstdint>
#include <limits>

#include <Eigen/Geometry>

#include "core/attitude_integrator.hpp"
#include "core/bias_tracker.hpp"
#include "core/heading_integrator.hpp"

namespace headingd::core {

struct Estimate {
  double t_s = 0.0;
  double heading_deg = 0.0;  // unwrapped integral of the bias-corrected z rate
  Eigen::Quaterniond attitude = Eigen::Quaterniond::Identity();
  Vec3 bias_dps = Vec3::Zero();
  Vec3 rate_dps = Vec3::Zero();  // bias-corrected
  double heading_sigma_deg = std::numeric_limits<double>::quiet_NaN();  // NaN: not provided
  bool in_startup = false;        // heading held while the start-up segment is measured
  std::uint64_t segment_index = 0;  // segment this sample belongs to
  SegmentVerdict closed;          // the segment this sample closed, if any
};

class Estimator {
 public:
  explicit Estimator(const BiasSettings& settings = kDefaultBiasSettings);

  const Estimate& update(const Sample& sample);
  const Estimate& last() const { return estimate_; }
  const BiasTracker& tracker() const { return tracker_; }
  BiasTracker& tracker() { return tracker_; }
  std::uint64_t samples() const { return samples_; }

 private:
  BiasTracker tracker_;
  HeadingIntegrator heading_;
  AttitudeIntegrator attitude_;
  Estimate estimate_;
  double previous_t_s_ = 0.0;
  std::uint64_t samples_ = 0;
};

}  // namespace headingd::core
