#include "dds/stop_hint.hpp"

#include <cmath>
#include <cstdio>

namespace headingd::app {

bool StopHintTracker::offer(const MotionReport& report, double now_s, std::string& why) {
  const auto refuse = [&](const std::string& reason) {
    ++refused_;
    why = reason;
    return false;
  };
  if (!report.linear_m_s.allFinite() || !report.angular_rad_s.allFinite())
    return refuse("a speed is not a finite number");
  if (report.stamp_s) {
    char text[96];
    if (!std::isfinite(*report.stamp_s)) return refuse("the stamp is not a finite time");
    const double age_s = now_s - *report.stamp_s;
    if (age_s > limits_.max_age_s) {
      std::snprintf(text, sizeof text, "stamped %.3f s ago (stale beyond %.3f s)", age_s, limits_.max_age_s);
      return refuse(text);
    }
    if (-age_s > limits_.max_future_s) {
      std::snprintf(text, sizeof text, "stamped %.3f s in the future", -age_s);
      return refuse(text);
    }
  }
  ++accepted_;
  last_received_s_ = now_s;
  const bool quiet = report.linear_m_s.norm() < settings_.linear_stopped_m_s &&
                     report.angular_rad_s.norm() < settings_.angular_stopped_rad_s;
  moving_ = !quiet;
  if (!quiet)
    quiet_since_s_.reset();
  else if (!quiet_since_s_)
    quiet_since_s_ = now_s;
  return true;
}

core::MotionHint StopHintTracker::hint(double now_s) const {
  if (!last_received_s_ || now_s - *last_received_s_ > settings_.stale_s) return core::MotionHint::None;
  if (moving_) return core::MotionHint::Moving;
  if (quiet_since_s_ && now_s - *quiet_since_s_ >= settings_.hold_s) return core::MotionHint::Stopped;
  return core::MotionHint::None;  // slowing down: not yet stopped long enough
}

const char* hint_name(core::MotionHint hint) {
  switch (hint) {
    case core::MotionHint::Stopped:
      return "stopped";
    case core::MotionHint::Moving:
      return "moving";
    case core::MotionHint::None:
      break;
  }
  return "none";
}

}  // namespace headingd::app
