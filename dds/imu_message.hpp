#pragma once
// The ROS 2 Imu's fields from an estimate, per REP-145 and the message's own rules: element 0
// of a covariance = -1 where we provide no estimate (the rate while the start-up segment has
// not yet measured the bias; linear acceleration, which a gyro has none of), all zeros only
// where the estimate exists and its uncertainty is unknown (the paper's methods), and never a
// zero variance that a filter would read as "exact". Plain values, no DDS: unit-testable.
#include <array>
#include <cstdint>

#include "core/diagnostics.hpp"
#include "core/estimate.hpp"
#include "dds/ros_settings.hpp"

namespace headingd::app {

// The bias-corrected rate summed over a publish interval: the Imu carries its mean, so a
// reader of 50 Hz messages gets all the information of a 400 Hz gyro, not one sample in eight.
class RateWindow {
 public:
  void add(const core::Vec3& rate_dps) {
    sum_dps_ += rate_dps;
    ++count_;
  }
  std::uint64_t count() const { return count_; }
  core::Vec3 mean_dps() const { return count_ > 0 ? core::Vec3(sum_dps_ / static_cast<double>(count_)) : sum_dps_; }
  void clear() {
    sum_dps_.setZero();
    count_ = 0;
  }

 private:
  core::Vec3 sum_dps_ = core::Vec3::Zero();
  std::uint64_t count_ = 0;
};

struct ImuFields {
  std::array<double, 4> orientation_xyzw{};
  std::array<double, 9> orientation_covariance{};
  std::array<double, 3> angular_velocity_rad_s{};
  std::array<double, 9> angular_velocity_covariance{};
  std::array<double, 9> linear_acceleration_covariance{};
};

// Roll and pitch, where not estimated: an angle known only to lie within +-pi.
inline constexpr double kUnknownAngleVarianceRad2 = 9.869604401089358;  // pi^2
// The smallest variance we state: below it a filter reads "exact" (zero means "unknown").
inline constexpr double kMinVarianceRad2 = 1e-12;

// The continuous yaw: heading minus the jumps that heading fixes made, rad.
double continuous_yaw_rad(const core::Estimate& estimate, const core::Diagnostics& diagnostics);

ImuFields imu_fields(const core::Estimate& estimate, const core::Diagnostics& diagnostics, const RateWindow& window,
                     const RosSettings& ros);

}  // namespace headingd::app
