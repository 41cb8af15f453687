#include "core/sample.hpp"

#include <cstdio>

namespace headingd::core {

std::optional<std::string> why_implausible(const Sample& s) {
  char text[160];
  if (!std::isfinite(s.t_s)) {
    std::snprintf(text, sizeof text, "time %g s is not a finite number", s.t_s);
    return text;
  }
  for (int axis = 0; axis < 3; ++axis) {
    const double rate = s.rate_dps[axis];
    if (!(std::abs(rate) <= kMaxPlausibleRateDps)) {
      std::snprintf(text, sizeof text, "rate %c = %g dps is beyond +-%g dps (no gyro measures that)", "xyz"[axis], rate,
                    kMaxPlausibleRateDps);
      return text;
    }
  }
  if (!std::isnan(s.temp_c) && !(s.temp_c >= kMinPlausibleTempC && s.temp_c <= kMaxPlausibleTempC)) {
    std::snprintf(text, sizeof text, "temperature %g degC is outside %g..%g degC", s.temp_c, kMinPlausibleTempC,
                  kMaxPlausibleTempC);
    return text;
  }
  return std::nullopt;
}

}  // namespace headingd::core
