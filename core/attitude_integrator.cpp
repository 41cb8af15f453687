#include "core/attitude_integrator.hpp"

#include <cmath>

#include "core/units.hpp"

namespace headingd::core {

void AttitudeIntegrator::add(const Vec3& rate_dps, double dt_s) {
  const Vec3 rotation_rad = rate_dps * (kRadPerDeg * dt_s);
  const double angle_rad = rotation_rad.norm();
  Eigen::Quaterniond step;
  if (angle_rad < 1e-12) {
    // First-order form avoids dividing by a vanishing angle.
    step = Eigen::Quaterniond(1.0, 0.5 * rotation_rad.x(), 0.5 * rotation_rad.y(), 0.5 * rotation_rad.z());
  } else {
    const double half = 0.5 * angle_rad;
    const Vec3 axis_sin = rotation_rad * (std::sin(half) / angle_rad);
    step = Eigen::Quaterniond(std::cos(half), axis_sin.x(), axis_sin.y(), axis_sin.z());
  }
  q_ = (q_ * step).normalized();
}

}  // namespace headingd::core
