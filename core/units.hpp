#pragma once
// Units used across headingd (one convention for the whole code base):
//   time      seconds, monotonic              (names end in _s)
//   rate      degrees per second              (names end in _dps)
//   angle     degrees, unless a name says rad (names end in _deg / _rad)
//   temp      degrees Celsius                 (names end in _c)
// Degrees per second is the L3GD20H's own unit (datasheet sensitivity is in mdps/LSB), so
// samples need no conversion on the hot path; radians appear only inside the quaternion math.
#include <numbers>

namespace headingd::core {

inline constexpr double kDegPerRad = 180.0 / std::numbers::pi;
inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;

constexpr double deg_to_rad(double deg) { return deg * kRadPerDeg; }
constexpr double rad_to_deg(double rad) { return rad * kDegPerRad; }

}  // namespace headingd::core
