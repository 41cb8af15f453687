#pragma once
// Full 3-D attitude from all three bias-corrected rates. The rate is taken as constant
// over each sample interval and the rotation it makes is applied exactly (quaternion
// exponential), so a constant rate is integrated without error whatever the step.
#include <Eigen/Geometry>
#include <cstddef>

#include "core/sample.hpp"

namespace headingd::core {

class AttitudeIntegrator {
 public:
  // Body-frame rate, dps; q <- q * exp(rate * dt / 2).
  void add(const Vec3& rate_dps, double dt_s) {
    const Turn turn{rate_dps.x(), rate_dps.y(), rate_dps.z(), dt_s};
    add_all(&turn, 1);
  }
  // One sample's body-frame rate (dps) and interval.
  struct Turn {
    double x_dps, y_dps, z_dps, dt_s;
  };
  // The same as add() on each in turn, to the same bits; the rotations are worked out first,
  // so that only the products wait for one another.
  void add_all(const Turn* turns, std::size_t count);
  void set_attitude(const Eigen::Quaterniond& q) {
    q_ = q.normalized();
    since_normalised_ = 0;
  }
  const Eigen::Quaterniond& attitude() const { return q_; }
  // The turn about the frame's vertical (its z) each body axis has made since construction, in
  // degrees: the integral of that axis's rate times the vertical's component along it. Their sum
  // is the yaw turned; each one is what a scale error of that axis alone multiplies. On a level
  // platform all of it is z's; a tilted one (a sensor on its side, a hand-held turn) yaws with x
  // and y too.
  const Vec3& vertical_turn_deg() const { return vertical_turn_deg_; }

 private:
  struct Step {
    double c, sx, sy, sz;  // cos(h), and sin(h) / angle times the rotation vector
  };
  static Step step_of(double x_dps, double y_dps, double z_dps, double dt_s);

  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
  Vec3 vertical_turn_deg_ = Vec3::Zero();
  unsigned since_normalised_ = 0;
};

}  // namespace headingd::core
