#pragma once
// Checks an inbound HeadingCommand before it touches the estimator: nothing malformed, out of
// range or stale moves the heading. Plain data in, verdict out: no DDS types, so it is easy to
// test and to fuzz.
#include <cstdint>
#include <optional>
#include <string>

#include "core/estimate.hpp"

namespace headingd::app {

enum class CommandKind : std::int32_t { SetHeading = 0, PlatformStopped = 1, PlatformMoving = 2, ClearHint = 3 };

struct CommandIn {
  std::int32_t stamp_sec = 0;
  std::uint32_t stamp_nanosec = 0;
  std::int32_t kind = 0;
  double heading_rad = 0.0;
  double heading_variance_rad2 = 0.0;
};

struct CommandLimits {
  double max_age_s = 5.0;            // older commands are stale
  double max_future_s = 1.0;         // clocks differ a little between hosts, not more
  double max_abs_heading_rad = 1e6;  // unwrapped, but not absurd
  double max_variance_rad2 = 10.0;
};

struct ValidCommand {
  CommandKind kind;
  double heading_deg = 0.0;
  double variance_deg2 = 0.0;
  core::MotionHint hint = core::MotionHint::None;
};

// `now_s` is the receiver's clock on the same epoch as the stamps (seconds). Returns the
// command, or the reason it was refused in `why`.
std::optional<ValidCommand> validate_command(const CommandIn& command, double now_s, const CommandLimits& limits,
                                             std::string& why);

}  // namespace headingd::app
