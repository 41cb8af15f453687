#pragma once
// Keeps the state file (bias, noise figures, temperature model) fresh: every save interval
// while running, and once more at the end, whatever ended the run. Not while the start-up
// segment is still measuring: that would overwrite a good saved bias with nothing.
#include <chrono>
#include <optional>
#include <string>

#include "core/estimator.hpp"
#include "pipeline/sink.hpp"

namespace headingd::pipeline {

class StateSink final : public BatchSink {
 public:
  StateSink(std::string path, double interval_s);
  void batch_done(const core::Estimator& estimator, const core::SampleSource& source) override;
  void finish(const core::Estimator& estimator, const core::SampleSource& source) override;

 private:
  void save(const core::Estimator& estimator);
  std::string path_;
  std::chrono::duration<double> interval_;
  std::chrono::steady_clock::time_point last_save_ = std::chrono::steady_clock::now();
};

// Restores the estimator from the state file; logs (notice) why not when it cannot.
void restore_state(core::Estimator& estimator, const std::string& path, bool with_heading = true);

}  // namespace headingd::pipeline
