#pragma once
// The paper's estimator: methods A, B, C (bias tracker) with rectangle-rule heading and
// quaternion attitude integration, bias in force at each sample.
#include <cstdint>

#include "core/attitude_integrator.hpp"
#include "core/bias_tracker.hpp"
#include "core/estimate.hpp"
#include "core/heading_integrator.hpp"

namespace headingd::core {

class PaperEstimator {
 public:
  PaperEstimator(Method method, const BiasSettings& settings);

  const Estimate& update(const Sample& sample);
  const Estimate& last() const { return estimate_; }
  const BiasTracker& tracker() const { return tracker_; }
  void set_bias(const Vec3& bias_dps) { tracker_.set_bias(bias_dps); }
  // Returns how far the heading moved.
  double set_heading(double heading_deg) {
    const double before_deg = heading_.heading_deg();
    heading_.set_heading_deg(heading_deg);
    return heading_deg - before_deg;
  }

 private:
  BiasTracker tracker_;
  HeadingIntegrator heading_;
  AttitudeIntegrator attitude_;
  Estimate estimate_;
  double previous_t_s_ = 0.0;
  bool started_ = false;
};

}  // namespace headingd::core
