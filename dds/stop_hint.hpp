#pragma once
// The vehicle's own motion (nav_msgs/Odometry or geometry_msgs/Twist[Stamped] from its
// controller) turned into the estimator's motion hint: both speeds below their thresholds for
// hold_s = stopped, either above = moving, nothing recent = no hint. Every message is checked
// as a HeadingCommand is (finite values, a stamp neither stale nor in the future) before it
// counts. Plain values, no DDS: unit-testable and fuzzable.
#include <cstdint>
#include <optional>
#include <string>

#include "core/estimate.hpp"
#include "dds/command_validator.hpp"
#include "dds/ros_settings.hpp"

namespace headingd::app {

struct MotionReport {
  std::optional<double> stamp_s;  // header stamp (Odometry, TwistStamped); Twist has none
  core::Vec3 linear_m_s = core::Vec3::Zero();
  core::Vec3 angular_rad_s = core::Vec3::Zero();
};

class StopHintTracker {
 public:
  StopHintTracker(const StopHintSettings& settings, const CommandLimits& limits)
      : settings_(settings), limits_(limits) {}
  // A message received at `now_s` (wall clock, the stamps' epoch). False, with the reason,
  // when it is refused; a refused message changes nothing.
  bool offer(const MotionReport& report, double now_s, std::string& why);
  // The hint in force at `now_s`.
  core::MotionHint hint(double now_s) const;
  std::uint64_t accepted() const { return accepted_; }
  std::uint64_t refused() const { return refused_; }

 private:
  StopHintSettings settings_;
  CommandLimits limits_;
  std::uint64_t accepted_ = 0, refused_ = 0;
  std::optional<double> last_received_s_;
  std::optional<double> quiet_since_s_;  // receive time of the first quiet message of the run
  bool moving_ = false;
};

const char* hint_name(core::MotionHint hint);

}  // namespace headingd::app
