#pragma once
// A progress line on standard error while a long replay runs, when it is a terminal: samples
// done, their rate, and (for a plain file, whose size says how much is left) the share done and
// the time left. Redrawn twice a second from the third second on, erased at the end.
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>

#include "pipeline/sink.hpp"

namespace headingd::pipeline {

class ProgressSink final : public BatchSink {
 public:
  using Fraction = std::function<std::optional<double>()>;  // 0..1 done, or nothing when unknown
  explicit ProgressSink(Fraction fraction);
  void batch_done(const core::Estimator& estimator, const core::SampleSource& source) override;
  void finish(const core::Estimator& estimator, const core::SampleSource& source) override;
  // Whether standard error is a terminal (no line otherwise: logs and pipes stay clean).
  static bool wanted();

 private:
  using Clock = std::chrono::steady_clock;
  Fraction fraction_;
  Clock::time_point start_ = Clock::now(), last_draw_{};
  bool drawn_ = false;
};

}  // namespace headingd::pipeline
