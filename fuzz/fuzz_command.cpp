// libFuzzer target: the HeadingCommand validator on every combination of field values,
// including NaN, infinities and extreme stamps.
#include <cmath>
#include <cstring>
#include <string>

#include "dds/command_validator.hpp"

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, std::size_t size) {
  headingd::app::CommandIn command;
  double now_s = 0.0;
  if (size < sizeof command.stamp_sec + sizeof command.stamp_nanosec + sizeof command.kind + 3 * sizeof(double))
    return 0;
  std::size_t at = 0;
  const auto take = [&](void* out, std::size_t n) {
    std::memcpy(out, data + at, n);
    at += n;
  };
  take(&command.stamp_sec, sizeof command.stamp_sec);
  take(&command.stamp_nanosec, sizeof command.stamp_nanosec);
  take(&command.kind, sizeof command.kind);
  take(&command.heading_rad, sizeof(double));
  take(&command.heading_variance_rad2, sizeof(double));
  take(&now_s, sizeof(double));
  std::string why;
  const auto valid = headingd::app::validate_command(command, now_s, {}, why);
  // What passes must be usable: finite numbers only.
  if (valid && (!std::isfinite(valid->heading_deg) || !std::isfinite(valid->variance_deg2) || valid->variance_deg2 < 0))
    __builtin_trap();
  if (!valid && why.empty()) __builtin_trap();
  return 0;
}
