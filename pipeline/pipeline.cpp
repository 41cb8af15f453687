#include "pipeline/pipeline.hpp"

#include <algorithm>
#include <exception>
#include <limits>
#include <span>

#include "io/csv_out.hpp"
#include "io/input_error.hpp"
#include "service/log.hpp"
#include "service/signals.hpp"

namespace headingd::pipeline {

const char* ending_name(Ending ending) {
  switch (ending) {
    case Ending::EndOfInput:
      return "end of input";
    case Ending::Duration:
      return "duration reached";
    case Ending::Signal:
      return "stopped by signal";
    case Ending::BadInput:
      return "bad input";
    case Ending::SourceFailed:
      return "sensor failed";
    case Ending::OutputFailed:
      return "output failed";
    case Ending::OutputClosed:
      return "output closed by its reader";
    case Ending::Refused:
      return "refused to run";
  }
  return "?";
}

Pipeline::Pipeline(core::SampleSource& source, std::unique_ptr<core::Estimator> estimator, PipelineOptions options)
    : source_(source), estimator_(std::move(estimator)), options_(options) {
  commands_.reserve(16);
}

void Pipeline::apply_commands() {
  inbox_->take(commands_);
  for (const auto& command : commands_) {
    if (command.kind == app::CommandKind::SetHeading)
      estimator_->set_heading(command.heading_deg, command.variance_deg2);
    else
      estimator_->set_motion_hint(command.hint);
  }
  commands_.clear();
}

double Pipeline::next_estimate_due_s() const {
  double due = std::numeric_limits<double>::infinity();
  for (const Sink* sink : sample_sinks_) due = std::min(due, sink->next_estimate_due_s());
  return due;
}

Outcome Pipeline::run() {
  Outcome outcome;
  std::vector<core::Sample> scratch(options_.batch);
  std::span<const core::Sample> batch;  // the samples read, in scratch or in the source's own memory
  bool started = false;                 // outcome.first_t_s is set
  const bool bulk = !options_.pacer && inbox_ == nullptr;
  std::size_t done = 0;  // samples of the current batch through the estimator and the sinks
  try {
    while (true) {
      if (stop_requested()) {
        outcome.ending = Ending::Signal;
        break;
      }
      std::size_t count = 0;
      done = 0;
      try {
        batch = source_.next(scratch);
        count = batch.size();
      } catch (const drivers::InputError& error) {
        outcome.ending = Ending::BadInput;
        outcome.error = error.what();
        outcome.exception = std::current_exception();
        break;
      } catch (const std::exception& error) {
        outcome.ending = Ending::SourceFailed;
        outcome.error = error.what();
        outcome.exception = std::current_exception();
        break;
      }
      if (count == 0) {
        outcome.ending = stop_requested() ? Ending::Signal : Ending::EndOfInput;
        break;
      }
      if (!started) {
        started = true;
        outcome.first_t_s = batch[0].t_s;
      }
      // The hot loop: nothing here that a batch can do once. A stop is seen per batch, or by
      // the pacer per sample (a recording in real time may sit in one batch for seconds).
      bool implausible = false;
      double due_s = bulk ? next_estimate_due_s() : 0.0;
      for (; done < count; ++done) {
        // A replay (no pacer, no commands): runs of samples no sink looks at go through the
        // estimator's fast path; it stops before a sample that closes a segment.
        if (bulk) {
          if (const std::size_t taken = estimator_->advance(batch.data() + done, count - done, due_s); taken > 0) {
            done += taken - 1;  // the loop's increment takes the last one
            continue;
          }
        }
        const core::Sample& sample = batch[done];
        // The estimator's door, for every source: a reader names file and line first; this
        // catches what a source let through (a driver bug, a new source).
        if (!core::plausible(sample)) {
          implausible = true;
          outcome.ending = Ending::BadInput;
          outcome.error = source_.describe() + ": sample " + std::to_string(outcome.samples + done + 1) + ": " +
                          *core::why_implausible(sample);
          break;
        }
        if (options_.pacer && !options_.pacer->wait(sample)) break;
        if (inbox_ != nullptr) apply_commands();
        const core::Estimate& estimate = estimator_->update(sample);
        for (Sink* sink : sample_sinks_) sink->add(sample, estimate, *estimator_);
        if (bulk) due_s = next_estimate_due_s();
      }
      outcome.samples += done;
      if (done > 0) outcome.last_t_s = batch[done - 1].t_s;
      done = 0;
      for (Sink* sink : sinks_) sink->batch_done(*estimator_, source_);
      if (estimator_->fault() && !outcome.estimator_fault) {
        outcome.estimator_fault = true;
        app::log(app::LogPriority::Error, "estimator fault",
                 "the estimator's state went non-finite (a bug past every input check): heading frozen at its last "
                 "finite value with an infinite sigma, the last healthy state kept for saving");
      }
      if (implausible) break;
      if (reloader_ && app::take_reload_request()) {
        if (auto next = reloader_(*estimator_)) estimator_ = std::move(next);
      }
      if (options_.duration_s > 0 && outcome.last_t_s - outcome.first_t_s >= options_.duration_s) {
        outcome.ending = Ending::Duration;
        break;
      }
    }
  } catch (const app::OutputClosed&) {
    outcome.ending = Ending::OutputClosed;
    outcome.samples += done;
  } catch (const RunRefused& refusal) {
    outcome.ending = Ending::Refused;
    outcome.error = refusal.what();
    outcome.samples += done;
  } catch (const std::exception& error) {  // a sink could not write (OutputError) or failed otherwise
    outcome.samples += done;               // those the sinks had taken before the failure
    outcome.ending = Ending::OutputFailed;
    outcome.error = error.what();
    outcome.exception = std::current_exception();
  }
  finish(outcome);
  return outcome;
}

void Pipeline::finish(Outcome& outcome) {
  for (auto sink = sinks_.rbegin(); sink != sinks_.rend(); ++sink) {
    try {
      (*sink)->finish(*estimator_, source_);
    } catch (const app::OutputClosed&) {
      const bool failed = outcome.ending == Ending::BadInput || outcome.ending == Ending::SourceFailed ||
                          outcome.ending == Ending::OutputFailed || outcome.ending == Ending::Refused;
      if (!failed) outcome.ending = Ending::OutputClosed;
    } catch (const std::exception& error) {
      if (outcome.ending != Ending::OutputFailed) {
        outcome.ending = Ending::OutputFailed;
        outcome.error = error.what();
        outcome.exception = std::current_exception();
      }
    }
  }
}

}  // namespace headingd::pipeline
