#include "dds/imu_message.hpp"

#include <algorithm>
#include <cmath>

#include "core/units.hpp"

namespace headingd::app {

double continuous_yaw_rad(const core::Estimate& e, const core::Diagnostics& d) {
  return core::deg_to_rad(e.heading_deg - d.heading_fix_offset_deg);
}

ImuFields imu_fields(const core::Estimate& e, const core::Diagnostics& d, const RateWindow& window,
                     const RosSettings& ros) {
  ImuFields f;
  if (ros.imu_orientation == ImuOrientation::YawOnly) {
    const double half_yaw = 0.5 * continuous_yaw_rad(e, d);
    f.orientation_xyzw = {0.0, 0.0, std::sin(half_yaw), std::cos(half_yaw)};
  } else {
    f.orientation_xyzw = {e.attitude.x(), e.attitude.y(), e.attitude.z(), e.attitude.w()};
  }
  const double sigma_rad = core::deg_to_rad(e.heading_sigma_deg);
  if (ros.orientation_stddev_rad || std::isfinite(sigma_rad)) {
    const double yaw_sigma = ros.orientation_stddev_rad ? *ros.orientation_stddev_rad : sigma_rad;
    f.orientation_covariance = {kUnknownAngleVarianceRad2,
                                0,
                                0,
                                0,
                                kUnknownAngleVarianceRad2,
                                0,
                                0,
                                0,
                                std::max(kMinVarianceRad2, yaw_sigma * yaw_sigma)};
  }  // else all zeros: the method gives no sigma ("covariance unknown")

  const core::Vec3 mean_rad_s = window.mean_dps() * core::kRadPerDeg;
  f.angular_velocity_rad_s = {mean_rad_s.x(), mean_rad_s.y(), mean_rad_s.z()};
  const core::Vec3 bias_sigma = e.bias_sigma_dps * core::kRadPerDeg;
  const core::Vec3 sample_sigma = d.sigma_still_dps * core::kRadPerDeg;
  if (e.in_startup || window.count() == 0) {
    // No bias measured yet: the rate is not an estimate of the platform's turn rate.
    f.angular_velocity_covariance[0] = -1.0;
  } else if (ros.angular_velocity_stddev_rad_s) {
    const double v =
        std::max(kMinVarianceRad2, *ros.angular_velocity_stddev_rad_s * *ros.angular_velocity_stddev_rad_s);
    f.angular_velocity_covariance = {v, 0, 0, 0, v, 0, 0, 0, v};
  } else if (bias_sigma.allFinite() && (sample_sigma.array() > 0.0).all()) {
    // The mean of n samples: their white noise averages down, the bias error taken off all of
    // them does not.
    const auto n = static_cast<double>(window.count());
    for (int a = 0; a < 3; ++a)
      f.angular_velocity_covariance[4 * static_cast<std::size_t>(a)] =
          std::max(kMinVarianceRad2, sample_sigma[a] * sample_sigma[a] / n + bias_sigma[a] * bias_sigma[a]);
  }  // else all zeros: no sigma from the paper's methods ("covariance unknown")
  f.linear_acceleration_covariance[0] = -1.0;  // a gyro: not provided
  if (e.fault) {                               // nothing we send is an estimate any more
    f.orientation_covariance = {-1, 0, 0, 0, 0, 0, 0, 0, 0};
    f.angular_velocity_covariance = {-1, 0, 0, 0, 0, 0, 0, 0, 0};
  }
  return f;
}

}  // namespace headingd::app
