#include "dds/command_validator.hpp"

#include <cmath>

#include "core/units.hpp"

namespace headingd::app {

std::optional<ValidCommand> validate_command(const CommandIn& c, double now_s, const CommandLimits& limits,
                                             std::string& why) {
  if (c.stamp_nanosec >= 1'000'000'000u) {
    why = "stamp.nanosec " + std::to_string(c.stamp_nanosec) + " is not below 1e9";
    return std::nullopt;
  }
  const double stamp_s = c.stamp_sec + c.stamp_nanosec * 1e-9;
  if (now_s - stamp_s > limits.max_age_s) {
    why =
        "stale: made " + std::to_string(now_s - stamp_s) + " s ago (limit " + std::to_string(limits.max_age_s) + " s)";
    return std::nullopt;
  }
  if (stamp_s - now_s > limits.max_future_s) {
    why = "stamped " + std::to_string(stamp_s - now_s) + " s in the future";
    return std::nullopt;
  }
  ValidCommand out{};
  switch (c.kind) {
    case static_cast<std::int32_t>(CommandKind::SetHeading):
      if (!std::isfinite(c.heading_rad) || std::abs(c.heading_rad) > limits.max_abs_heading_rad) {
        why = "heading_rad is not a finite number within +-" + std::to_string(limits.max_abs_heading_rad);
        return std::nullopt;
      }
      if (!std::isfinite(c.heading_variance_rad2) || c.heading_variance_rad2 < 0.0 ||
          c.heading_variance_rad2 > limits.max_variance_rad2) {
        why = "heading_variance_rad2 must be within [0, " + std::to_string(limits.max_variance_rad2) + "]";
        return std::nullopt;
      }
      out.kind = CommandKind::SetHeading;
      out.heading_deg = core::rad_to_deg(c.heading_rad);
      out.variance_deg2 = c.heading_variance_rad2 * core::kDegPerRad * core::kDegPerRad;
      return out;
    case static_cast<std::int32_t>(CommandKind::PlatformStopped):
      out.kind = CommandKind::PlatformStopped;
      out.hint = core::MotionHint::Stopped;
      return out;
    case static_cast<std::int32_t>(CommandKind::PlatformMoving):
      out.kind = CommandKind::PlatformMoving;
      out.hint = core::MotionHint::Moving;
      return out;
    case static_cast<std::int32_t>(CommandKind::ClearHint):
      out.kind = CommandKind::ClearHint;
      out.hint = core::MotionHint::None;
      return out;
    default:
      why = "unknown command kind " + std::to_string(c.kind);
      return std::nullopt;
  }
}

}  // namespace headingd::app
