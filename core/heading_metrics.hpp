#pragma once
// The paper's error metrics for E(t) = theta_true(t) - theta_gyro(t) (docs/algorithm.md):
// max |E|, final |E|, RMS and drift rate (final |E| per hour). Streaming, no storage.
#include <cmath>
#include <cstdint>

namespace headingd::core {

class HeadingMetrics {
 public:
  void add(double t_s, double error_deg) {
    if (count_ == 0) first_t_s_ = t_s;
    ++count_;
    last_t_s_ = t_s;
    final_abs_deg_ = std::abs(error_deg);
    if (final_abs_deg_ > max_abs_deg_) max_abs_deg_ = final_abs_deg_;
    sum_squares_ += error_deg * error_deg;
  }
  std::uint64_t count() const { return count_; }
  double hours() const { return (last_t_s_ - first_t_s_) / 3600.0; }
  double max_abs_deg() const { return max_abs_deg_; }
  double final_abs_deg() const { return final_abs_deg_; }
  double rms_deg() const { return count_ ? std::sqrt(sum_squares_ / static_cast<double>(count_)) : 0.0; }
  double drift_deg_per_h() const { return hours() > 0 ? final_abs_deg_ / hours() : 0.0; }

 private:
  std::uint64_t count_ = 0;
  double first_t_s_ = 0.0;
  double last_t_s_ = 0.0;
  double max_abs_deg_ = 0.0;
  double final_abs_deg_ = 0.0;
  double sum_squares_ = 0.0;
};

}  // namespace headingd::core
