#pragma once
// Records what the source delivered (`run --record`, `record`) as a native CSV that replays to
// the very same estimates.
#include <chrono>
#include <cstdint>
#include <string>

#include "io/native_csv.hpp"
#include "pipeline/sink.hpp"

namespace headingd::pipeline {

class RecordingSink final : public Sink {
 public:
  // `comments`: the source's provenance, '#' lines. Throws OutputError.
  RecordingSink(const std::string& path, const std::string& comments);
  void add(const core::Sample& sample, const core::Estimate& estimate, const core::Estimator& estimator) override;
  // Ends the file with the measured rate and the sample counts.
  void finish(const core::Estimator& estimator, const core::SampleSource& source) override;
  // Ends the file with `last_line` (a '#' comment) instead, mid-run: a series split by time.
  void close(const std::string& last_line);
  const std::string& path() const { return writer_.path(); }
  // Samples of this file were handed to the system without an error (a full disk has taken them).
  bool samples_on_disk() const { return samples_on_disk_; }

 private:
  app::RecordingWriter writer_;
  unsigned since_check_ = 0;
  std::uint64_t samples_written_ = 0;
  bool samples_on_disk_ = false;
  std::chrono::steady_clock::time_point last_push_ = std::chrono::steady_clock::now();
};

}  // namespace headingd::pipeline
