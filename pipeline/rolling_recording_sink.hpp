#pragma once
// The last hours of the sensor's samples kept on disk, for a vehicle that runs for months: a
// black box to replay when its heading is questioned. A series of recordings in one directory,
// DIR/headingd-YYYYmmddTHHMMSSZ.csv.zst (UTC at the file's first sample): a new file every
// `split_hours` of samples and at every start, so a restart never overwrites what was recorded;
// the series' files older than `keep_hours` are deleted as each new one starts, so the disk
// holds a bounded window. Each file is a whole recording (the sensor's provenance header, a
// closing line naming the next) that replays on its own.
#include <cstdint>
#include <optional>
#include <string>

#include "pipeline/recording_sink.hpp"

namespace headingd::pipeline {

struct RollingSettings {
  std::string dir;           // "" = no rolling recording
  double split_hours = 1.0;  // a new file after this much sample time
  double keep_hours = 48.0;  // files that started longer ago than this are deleted (0: none kept but the current)
};

class RollingRecordingSink final : public Sink {
 public:
  using WallClock = double (*)();  // UTC seconds, for the names and the ages
  // Creates the directory if need be; the first file is started by the first sample. Throws
  // OutputError.
  RollingRecordingSink(RollingSettings settings, std::string comments, WallClock wall);
  void add(const core::Sample& sample, const core::Estimate& estimate, const core::Estimator& estimator) override;
  void finish(const core::Estimator& estimator, const core::SampleSource& source) override;
  // The file being written ("" before the first sample) and how many were started.
  std::string path() const { return current_ ? current_->path() : std::string(); }
  std::uint64_t files_started() const { return files_started_; }
  std::uint64_t files_deleted() const { return files_deleted_; }

 private:
  void start_file(double t_s);
  void delete_expired();

  RollingSettings settings_;
  std::string comments_;
  WallClock wall_;
  std::optional<RecordingSink> current_;
  double file_start_t_s_ = 0.0;
  std::uint64_t files_started_ = 0;
  std::uint64_t files_deleted_ = 0;
};

// The time in a series file's name (UTC seconds), or nothing for any other name.
std::optional<double> rolling_file_time(const std::string& name);

}  // namespace headingd::pipeline
