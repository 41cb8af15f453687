#pragma once
#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

namespace headingd::core {

using Vec3 = Eigen::Vector3d;

// One gyro reading as every source (live chip, replay, simulator) delivers it.
struct Sample {
  double t_s = 0.0;                                          // monotonic time stamp
  Vec3 rate_dps = Vec3::Zero();                              // x, y, z angular rate, sensor frame
  double temp_c = std::numeric_limits<double>::quiet_NaN();  // NaN when the source has none
};

// The one rule at the estimator's door, whatever the source: what a gyro can physically report.
// The widest MEMS gyros reach +-4000 dps (the L3GD20H +-2000); die temperatures stay within
// the automotive range with margin. A temperature may be unknown (NaN), nothing else may.
inline constexpr double kMaxPlausibleRateDps = 10000.0;
inline constexpr double kMinPlausibleTempC = -60.0;
inline constexpr double kMaxPlausibleTempC = 150.0;

inline bool plausible(const Sample& s) {
  // Each comparison is false for a NaN: a NaN rate or time fails, a NaN temperature passes.
  return std::abs(s.t_s) <= std::numeric_limits<double>::max() && std::abs(s.rate_dps.x()) <= kMaxPlausibleRateDps &&
         std::abs(s.rate_dps.y()) <= kMaxPlausibleRateDps && std::abs(s.rate_dps.z()) <= kMaxPlausibleRateDps &&
         !(s.temp_c < kMinPlausibleTempC) && !(s.temp_c > kMaxPlausibleTempC);
}

// Empty when plausible; otherwise what is wrong, with the value.
std::optional<std::string> why_implausible(const Sample& s);

}  // namespace headingd::core
