#pragma once
// Where estimates go. A sink is told every sample with its estimate, then once per batch the
// source delivered (for work at a slower pace: saving, status), then once at the end,
// whatever ended the run. Sinks are finished in the reverse of the order they were added, so
// the last one set up is the first one taken down (as chrony's main.c undoes its start-up).
#include <limits>
#include <stdexcept>
#include <vector>

#include "core/estimate.hpp"
#include "core/estimator.hpp"
#include "core/sample.hpp"
#include "core/sample_source.hpp"
#include "dds/command_validator.hpp"

namespace headingd::pipeline {

// Thrown by a sink that must end the run for a reason of its own rather than a failure to
// write (another instance publishing our topics, under the refuse policy).
class RunRefused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Sink {
 public:
  virtual ~Sink() = default;
  // Every sample, in order, with the estimate it produced. May throw OutputError.
  virtual void add(const core::Sample& sample, const core::Estimate& estimate, const core::Estimator& estimator) = 0;
  // False for sinks that only act per batch and at the end: the hot loop skips their add().
  virtual bool wants_samples() const { return true; }
  // The earliest sample time whose estimate this sink needs next: samples before it may go by
  // without add(), except those that close a segment (a replay's estimates at 10 Hz). The
  // default, minus infinity, asks for every sample.
  virtual double next_estimate_due_s() const { return -std::numeric_limits<double>::infinity(); }
  // After each batch from the source. May throw OutputError.
  virtual void batch_done(const core::Estimator& /*estimator*/, const core::SampleSource& /*source*/) {}
  // Once, at the end of the run, whatever ended it. May throw OutputError; the other sinks
  // are finished all the same.
  virtual void finish(const core::Estimator& /*estimator*/, const core::SampleSource& /*source*/) {}
};

// A sink that acts only per batch and at the end (saving, status): the hot loop skips it.
class BatchSink : public Sink {
 public:
  void add(const core::Sample& /*sample*/, const core::Estimate& /*estimate*/,
           const core::Estimator& /*estimator*/) final {}
  bool wants_samples() const final { return false; }
};

// Commands from outside (HeadingCommand over DDS), as plain validated values.
class CommandInbox {
 public:
  virtual ~CommandInbox() = default;
  // Appends the commands received since the last call.
  virtual void take(std::vector<app::ValidCommand>& out) = 0;
};

}  // namespace headingd::pipeline
