#include "hw/sensor_limits.hpp"

#include "hw/l3gd20h_registers.hpp"

namespace headingd::drivers {

using namespace l3gd20h;

std::optional<std::string> address_not_allowed(long long address) {
  if (address == kAddressLow || address == kAddressHigh) return std::nullopt;
  return "0x6A or 0x6B";
}

std::optional<std::string> rate_not_allowed(long long rate_hz) {
  for (const auto& rate : kRates)
    if (rate.nominal_hz == rate_hz) return std::nullopt;
  return "100, 200, 400 or 800";
}

std::optional<std::string> bandwidth_not_allowed(long long code) {
  if (code >= 0 && code <= 3) return std::nullopt;
  return "0, 1, 2 or 3";
}

std::optional<std::string> full_scale_not_allowed(long long dps) {
  for (const auto& scale : kScales)
    if (scale.full_scale_dps == dps) return std::nullopt;
  return "245, 500 or 2000";
}

std::optional<std::string> watermark_not_allowed(long long samples) {
  if (samples >= 1 && samples <= 30) return std::nullopt;
  return "1 to 30";
}

}  // namespace headingd::drivers
