#pragma once
// Tells systemd and the journal how the run goes: READY=1 after the first batch, WATCHDOG=1
// from the loop, a STATUS= line every 10 s, a warning when the bias restarts from an
// unexplained quiet period (a notice when a restart is taken back or mends the heading), and
// STOPPING=1 at the end, whatever ended the run.
#include <chrono>
#include <cstdint>

#include "pipeline/sink.hpp"
#include "service/notify.hpp"

namespace headingd::pipeline {

class ServiceSink final : public BatchSink {
 public:
  explicit ServiceSink(app::Notifier& notifier) : notifier_(notifier) {}
  void batch_done(const core::Estimator& estimator, const core::SampleSource& source) override;
  void finish(const core::Estimator& estimator, const core::SampleSource& source) override;

 private:
  app::Notifier& notifier_;
  std::chrono::steady_clock::time_point last_status_ = std::chrono::steady_clock::now();
  std::uint64_t recoveries_seen_ = 0;
  std::uint64_t saved_bias_restarts_seen_ = 0;
  std::uint64_t trail_restarts_seen_ = 0;
  std::uint64_t saved_noise_replaced_seen_ = 0;
  std::uint64_t refuted_models_seen_ = 0;
  std::uint64_t taken_back_seen_ = 0;
  std::uint64_t returns_mended_seen_ = 0;
  std::uint64_t gaps_seen_ = 0;
};

}  // namespace headingd::pipeline
