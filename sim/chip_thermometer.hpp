#pragma once
// The die temperature as the L3GD20H reports it, for benches and tests that feed an estimator
// directly: OUT_TEMP holds whole degrees (-1 LSB/degC) refreshed at 1 Hz (datasheet section 7.8,
// Table 5); hw/l3gd20h.cpp reads it as 25 - OUT_TEMP and sim/l3gd20h_sim.cpp writes
// lround(25 - T), so the value is 25 - lround(25 - T), held for a second.
#include <cmath>

namespace headingd::drivers {

class ChipThermometer {
 public:
  double read(double t_s, double true_c) {
    if (t_s >= next_refresh_s_) {
      held_c_ = 25.0 - static_cast<double>(std::lround(25.0 - true_c));
      next_refresh_s_ = t_s + 1.0;
    }
    return held_c_;
  }

 private:
  double held_c_ = 0.0;
  double next_refresh_s_ = 0.0;
};

}  // namespace headingd::drivers
