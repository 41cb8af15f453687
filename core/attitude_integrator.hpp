#pragma once
// Full 3-D attitude from all three bias-corrected rates. The rate is taken as constant
// over each sample interval and the rotation it makes is applied exactly (quaternion
// exponential), so a constant rate is integrated without error whatever the step.
#include <Eigen/Geometry>

#include "core/sample.hpp"

namespace headingd::core {

class AttitudeIntegrator {
 public:
  // Body-frame rate, dps; q <- q * exp(rate * dt / 2).
  void add(const Vec3& rate_dps, double dt_s);
  void set_attitude(const Eigen::Quaterniond& q) {
    q_ = q.normalized();
    since_normalised_ = 0;
  }
  const Eigen::Quaterniond& attitude() const { return q_; }

 private:
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
  unsigned since_normalised_ = 0;
};

}  // namespace headingd::core
