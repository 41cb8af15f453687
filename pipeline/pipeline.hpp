#pragma once
// The one sample loop of headingd. Every command that turns samples into estimates — run
// (sensor or recording), replay, record, allan --still-only, the soak and the benchmarks —
// builds a Pipeline and calls run():
//
//   source --read--> [pacer] --> inbound commands --> Estimator --> sinks (in order)
//                                                                 \-> per batch: sinks, SIGHUP
//
// Whatever ends the run (end of input, signal, --duration, bad input, a dead sensor, an
// output that cannot be written) the sinks are finished in reverse order from one place, so
// the state is saved, STOPPING is sent and outputs are flushed on every path.
#include <atomic>
#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/estimator.hpp"
#include "core/sample_source.hpp"
#include "pipeline/pacer.hpp"
#include "pipeline/sink.hpp"

namespace headingd::pipeline {

enum class Ending {
  EndOfInput,    // the source had nothing more
  Duration,      // --duration reached
  Signal,        // SIGINT/SIGTERM (or another stop request)
  BadInput,      // the recording has a bad line: estimates up to it are kept
  SourceFailed,  // the sensor is gone for good
  OutputFailed,  // an output could not be written
  OutputClosed,  // the reader of our standard output went away: a quiet end
  Refused,       // a sink ended the run on purpose (another instance came first)
};

struct Outcome {
  Ending ending = Ending::EndOfInput;
  std::string error;             // what went wrong, for the three failures
  std::exception_ptr exception;  // the exception behind it, to rethrow
  std::uint64_t samples = 0;     // estimated (across reloads)
  double first_t_s = 0.0;
  double last_t_s = 0.0;
  bool estimator_fault = false;  // the output invariant tripped (Estimate::fault)
};

const char* ending_name(Ending ending);

struct PipelineOptions {
  std::size_t batch = 64;                   // samples per read
  double duration_s = 0.0;                  // stop once this much sample time has passed (0: never)
  const std::atomic<bool>* stop = nullptr;  // raised by signals
  std::optional<Pacer> pacer;               // none: as fast as the source delivers
};

class Pipeline {
 public:
  Pipeline(core::SampleSource& source, std::unique_ptr<core::Estimator> estimator, PipelineOptions options);

  // Sinks are told in the order added and finished in reverse. Not owned.
  void add_sink(Sink& sink) {
    sinks_.push_back(&sink);
    if (sink.wants_samples()) sample_sinks_.push_back(&sink);
  }
  void set_inbox(CommandInbox* inbox) { inbox_ = inbox; }
  // Called after a batch when SIGHUP asked for a reload; returns the estimator to go on with,
  // or null to keep the running one.
  using Reloader = std::function<std::unique_ptr<core::Estimator>(const core::Estimator&)>;
  void set_reloader(Reloader reloader) { reloader_ = std::move(reloader); }

  Outcome run();

  const core::Estimator& estimator() const { return *estimator_; }
  core::Estimator& estimator() { return *estimator_; }

 private:
  bool stop_requested() const { return options_.stop != nullptr && options_.stop->load(); }
  void apply_commands();
  // The earliest sample time any sink needs the estimate of: a replay takes the samples
  // before it through Estimator::advance.
  double next_estimate_due_s() const;
  void finish(Outcome& outcome);

  core::SampleSource& source_;
  std::unique_ptr<core::Estimator> estimator_;
  PipelineOptions options_;
  std::vector<Sink*> sinks_;
  std::vector<Sink*> sample_sinks_;  // those of sinks_ that want every sample
  CommandInbox* inbox_ = nullptr;
  Reloader reloader_;
  std::vector<app::ValidCommand> commands_;
};

}  // namespace headingd::pipeline
