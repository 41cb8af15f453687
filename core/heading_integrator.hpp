#pragma once
// Heading as the paper integrates it: theta_n = theta_{n-1} + (x_n - b_n) * dt_n, the
// rectangular rule over the z rate with the bias in force at that sample. Unwrapped.
namespace headingd::core {

class HeadingIntegrator {
 public:
  void add(double rate_z_dps, double bias_z_dps, double dt_s) { heading_deg_ += (rate_z_dps - bias_z_dps) * dt_s; }
  void set_heading_deg(double heading_deg) { heading_deg_ = heading_deg; }
  double heading_deg() const { return heading_deg_; }

 private:
  double heading_deg_ = 0.0;
};

}  // namespace headingd::core
