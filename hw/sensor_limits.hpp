#pragma once
// The values the L3GD20H accepts for each operator-visible setting, checked in this one place:
// the configuration parser reports a bad value with its file and line, the driver refuses one
// at start. Each function returns nothing for an allowed value, else the allowed values as
// text ("100, 200, 400 or 800"). Values from the datasheet (DS 5.1.1 address, 7.2 CTRL1 ODR
// and bandwidth, 7.5 CTRL4 full scale, 7.14 FIFO_CTRL threshold).
#include <optional>
#include <string>

namespace headingd::drivers {

std::optional<std::string> address_not_allowed(long long address);
std::optional<std::string> rate_not_allowed(long long rate_hz);
std::optional<std::string> bandwidth_not_allowed(long long code);
std::optional<std::string> full_scale_not_allowed(long long dps);
std::optional<std::string> watermark_not_allowed(long long samples);

}  // namespace headingd::drivers
