#pragma once
// Recordings replayed one after another as one run: a rolling series (`run --record-dir`) that
// was split by time, or a recording cut into parts. The estimator carries on from one file into
// the next, as the daemon did while it wrote them, so the estimates are those of the whole run
// rather than of a cold start at every file's beginning. Each file must go on in time from the
// one before; one that does not (files of two runs, or given out of order) is an InputError
// naming both files, after every sample before it.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/sample_source.hpp"
#include "io/csv_replay.hpp"

namespace headingd::drivers {

// Where a file sits in a rolling series, from the line its header carries ("rolling series run
// NAME, file N"); nothing for any other file, or one whose header cannot be read. A wall clock
// stepped back mid-run gives later files earlier names: this order does not move with it.
struct SeriesPosition {
  std::string run;  // the run's first file's name, without its ending
  long file = 0;    // 1 for the run's first file
};
std::optional<SeriesPosition> series_position(const std::string& path);

class JoinedReplaySource final : public core::SampleSource {
 public:
  // Opens the first file (OpenError, InputError); the others when their turn comes. A later part
  // that cannot be opened, or whose reading fails (cut short: a rolling file lost to a full disk
  // keeps what fit), is a damaged part: its good samples are replayed, the replay goes on with the
  // next, and damaged_parts() says what was wrong. The last part's read error is thrown as any
  // recording's is.
  // `split_runs`: where one run of the recorder ended, read() returns 0 as at an end, and
  // next_run() goes on with the next run (a fleet's folder replayed as a row per run). Without
  // it a run that follows in time is carried on (run_boundaries()), one after a reboot is an
  // InputError that says so. Where runs end: a rolling series' files name their run (a crash and
  // a restart on the same boot, a lost file between two runs: told apart); files that do not
  // (a series written before they did) end a run at the recorder's end-of-run line, or at a part
  // cut short followed by a clock that starts again (a crash, then a reboot).
  explicit JoinedReplaySource(std::vector<std::string> paths, bool split_runs = false);
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
  // After read() returned 0: true when another run follows (its counts start again: read the
  // run's health, boundaries and damage first); false at the real end.
  bool next_run();
  // The file the samples now come from (after next_run(): the new run's first).
  const std::string& current_file() const { return paths_[std::min(index_, paths_.size() - 1)]; }

 private:
  void open_next();
  void note_damage(const std::string& error);
  void take(std::span<const core::Sample> samples);

  std::vector<std::string> paths_;
  std::size_t index_ = 0;
  std::unique_ptr<CsvReplaySource> current_;
  bool current_started_ = false;
  bool split_runs_ = false;
  bool after_run_end_ = false;      // the file before the current one ended a run
  bool runs_named_ = false;         // both name their series run: after_run_end_ says it all
  std::string current_run_;         // the series run the current file names ("" if none)
  std::string run_;                 // ... and the one the last sample came from
  bool after_damage_ = false;       // a damaged part came after the last good sample
  bool run_ended_ = false;          // read() says "end" until next_run()
  std::vector<core::Sample> held_;  // the next run's first samples, read to see that it was one
  std::vector<RunBoundary> boundaries_;
  std::vector<DamagedPart> damaged_;
  std::string description_;
  std::string last_part_;  // the file the last sample came from
  std::uint64_t samples_ = 0;
  double first_t_s_ = 0.0;
  double last_t_s_ = 0.0;
};

}  // namespace headingd::drivers
