#pragma once
// A file output a live run can go on without: the recording, or the estimates CSV, beside
// DDS. When it cannot be written (a full disk, a mount gone) it is dropped — logged as an
// error, counted for Status and /diagnostics — and the heading keeps being published, where
// ending the run would take the vehicle's heading down with a side file, and systemd's
// restart would meet the same full disk again. What was written stays on disk as it was.
#include <cstdint>
#include <string>

#include "pipeline/sink.hpp"

namespace headingd::pipeline {

// The outputs dropped so far, shared by the run's expendable sinks and read by its reporters.
struct OutputDrops {
  std::uint64_t count = 0;
  std::string last;  // what the last one could not do
  // Of them, the outputs not writing now: a dropped file for the rest of the run, a rolling
  // series only until its next file works (then /diagnostics is OK again, the count stays).
  std::uint64_t failing = 0;
};

class ExpendableSink final : public Sink {
 public:
  // `inner` is not owned; `what` names it in the log ("recording", "estimates output").
  ExpendableSink(Sink& inner, std::string what, OutputDrops& drops);
  void add(const core::Sample& sample, const core::Estimate& estimate, const core::Estimator& estimator) override;
  bool wants_samples() const override { return inner_.wants_samples(); }
  double next_estimate_due_s() const override;
  void batch_done(const core::Estimator& estimator, const core::SampleSource& source) override;
  void finish(const core::Estimator& estimator, const core::SampleSource& source) override;
  bool dropped() const { return dropped_; }

 private:
  template <typename Call>
  void guarded(Call call);
  void drop(const std::string& why);

  Sink& inner_;
  std::string what_;
  OutputDrops& drops_;
  bool dropped_ = false;
};

}  // namespace headingd::pipeline
