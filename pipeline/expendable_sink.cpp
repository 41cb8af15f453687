#include "pipeline/expendable_sink.hpp"

#include <limits>

#include "io/csv_out.hpp"
#include "service/log.hpp"

namespace headingd::pipeline {

ExpendableSink::ExpendableSink(Sink& inner, std::string what, OutputDrops& drops)
    : inner_(inner), what_(std::move(what)), drops_(drops) {}

// OutputClosed (the reader of our standard output went away) is not caught: that ends the run
// quietly, as it always has. Only a write that failed drops the output.
template <typename Call>
void ExpendableSink::guarded(Call call) {
  if (dropped_) return;  // once dropped, not even its last words: they could not be written either
  try {
    call();
  } catch (const app::OutputClosed&) {
    throw;
  } catch (const app::OutputError& error) {
    drop(error.what());
  }
}

void ExpendableSink::add(const core::Sample& sample, const core::Estimate& estimate, const core::Estimator& estimator) {
  guarded([&] { inner_.add(sample, estimate, estimator); });
}

double ExpendableSink::next_estimate_due_s() const {
  return dropped_ ? std::numeric_limits<double>::infinity() : inner_.next_estimate_due_s();
}

void ExpendableSink::batch_done(const core::Estimator& estimator, const core::SampleSource& source) {
  guarded([&] { inner_.batch_done(estimator, source); });
}

void ExpendableSink::finish(const core::Estimator& estimator, const core::SampleSource& source) {
  guarded([&] { inner_.finish(estimator, source); });
}

void ExpendableSink::drop(const std::string& why) {
  dropped_ = true;
  ++drops_.count;
  ++drops_.failing;
  drops_.last = what_ + ": " + why;
  app::log(app::LogPriority::Error, "output dropped " + what_,
           "the " + what_ + " could not be written and is dropped (" + why +
               "); what it holds so far stays on disk; heading and status are still published");
}

}  // namespace headingd::pipeline
