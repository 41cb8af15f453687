#include "pipeline/recording_sink.hpp"

#include <cstdio>

namespace headingd::pipeline {

RecordingSink::RecordingSink(const std::string& path, const std::string& comments)
    : writer_(path, comments, app::RecordingPrecision{}) {}

void RecordingSink::add(const core::Sample& sample, const core::Estimate& /*estimate*/,
                        const core::Estimator& /*estimator*/) {
  writer_.add(sample);
  ++samples_written_;
  // Once a wall-clock second: a crash loses at most that much of the recording.
  if (++since_check_ >= 64) {
    since_check_ = 0;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_push_ >= std::chrono::seconds(1)) {
      writer_.push();
      last_push_ = now;
      samples_on_disk_ = true;
    }
  }
}

void RecordingSink::finish(const core::Estimator& /*estimator*/, const core::SampleSource& source) {
  const core::SourceHealth health = source.health();
  char text[200];
  std::snprintf(text, sizeof text, "# %s %.3f Hz; %llu samples, %llu lost", app::kEndOfRunComment, health.rate_hz,
                static_cast<unsigned long long>(health.samples), static_cast<unsigned long long>(health.lost_samples));
  if (samples_written_ != health.samples)  // the last file of a rolling series holds part of the run
    std::snprintf(text, sizeof text, "# %s %.3f Hz; the run: %llu samples, %llu lost; this file: %llu",
                  app::kEndOfRunComment, health.rate_hz, static_cast<unsigned long long>(health.samples),
                  static_cast<unsigned long long>(health.lost_samples),
                  static_cast<unsigned long long>(samples_written_));
  writer_.comment(text);
  writer_.close();
}

void RecordingSink::close(const std::string& last_line) {
  writer_.comment(last_line);
  writer_.close();
}

}  // namespace headingd::pipeline
