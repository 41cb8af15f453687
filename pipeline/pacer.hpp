#pragma once
// How fast samples enter the estimator. A sensor paces itself (its FIFO fills at the chip's
// rate), so live runs use no pacer; a recording is paced by its own clock: in real time, at a
// factor of it, or as fast as it can be read (`--speed realtime|FACTOR|max`).
#include <atomic>
#include <chrono>
#include <optional>
#include <string>

#include "core/sample.hpp"

namespace headingd::pipeline {

class Pacer {
 public:
  // factor > 0: sample time t is due at start + (t - t0) / factor. `stop` ends a wait early.
  Pacer(double factor, const std::atomic<bool>* stop);
  // Waits until the sample is due; false if the stop flag was raised meanwhile.
  bool wait(const core::Sample& sample);
  double factor() const { return factor_; }

 private:
  double factor_;
  const std::atomic<bool>* stop_;
  bool started_ = false;
  double first_t_s_ = 0.0;
  std::chrono::steady_clock::time_point start_{};
};

// "max" (no pacing: nullopt factor 0), "realtime" (1) or a positive factor; nullopt when the
// text is none of these.
std::optional<double> parse_speed(const std::string& text);

}  // namespace headingd::pipeline
