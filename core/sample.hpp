#pragma once
#include <Eigen/Core>
#include <limits>

namespace headingd::core {

using Vec3 = Eigen::Vector3d;

// One gyro reading as every source (live chip, replay, simulator) delivers it.
struct Sample {
  double t_s = 0.0;                                          // monotonic time stamp
  Vec3 rate_dps = Vec3::Zero();                              // x, y, z angular rate, sensor frame
  double temp_c = std::numeric_limits<double>::quiet_NaN();  // NaN when the source has none
};

}  // namespace headingd::core
