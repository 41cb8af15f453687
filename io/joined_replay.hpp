#pragma once
// Recordings replayed one after another as one run: a rolling series (`run --record-dir`) that
// was split by time, or a recording cut into parts. The estimator carries on from one file into
// the next, as the daemon did while it wrote them, so the estimates are those of the whole run
// rather than of a cold start at every file's beginning. Each file must go on in time from the
// one before; one that does not (files of two runs, or given out of order) is an InputError
// naming both files, after every sample before it.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/sample_source.hpp"
#include "io/csv_replay.hpp"

namespace headingd::drivers {

class JoinedReplaySource final : public core::SampleSource {
 public:
  // Opens the first file (OpenError, InputError); the others when their turn comes. A later part
  // that cannot be opened, or whose reading fails (cut short: a rolling file lost to a full disk
  // keeps what fit), is a damaged part: its good samples are replayed, the replay goes on with the
  // next, and damaged_parts() says what was wrong. The last part's read error is thrown as any
  // recording's is.
  explicit JoinedReplaySource(std::vector<std::string> paths);
  std::size_t read(std::span<core::Sample> out) override;
  void close() override;
  std::string describe() const override { return description_; }  // fixed at open: read-ahead asks from its thread
  core::SourceHealth health() const override;
  // The files done and the current one's share of itself, over all of them.
  std::optional<double> fraction_read() const;
  // Where one run of the recorder ended and the next file began another (the file before closes
  // with the end-of-run line RecordingSink writes, not "continued in …"): the daemon restarted
  // there, from its state file, where this replay carries the estimator on across the gap.
  struct RunBoundary {
    std::string file;  // the first file of the next run
    double gap_s;      // from the last sample before it to its first
  };
  const std::vector<RunBoundary>& run_boundaries() const { return boundaries_; }
  struct DamagedPart {
    std::string file;
    std::string error;
  };
  const std::vector<DamagedPart>& damaged_parts() const { return damaged_; }

 private:
  void open_next();

  std::vector<std::string> paths_;
  std::size_t index_ = 0;
  std::unique_ptr<CsvReplaySource> current_;
  bool current_started_ = false;
  bool after_run_end_ = false;  // the file before the current one ended a run
  std::vector<RunBoundary> boundaries_;
  std::vector<DamagedPart> damaged_;
  std::string description_;
  std::string last_part_;  // the file the last sample came from
  std::uint64_t samples_ = 0;
  double first_t_s_ = 0.0;
  double last_t_s_ = 0.0;
};

}  // namespace headingd::drivers
