#pragma once
// The last hours of the sensor's samples kept on disk, for a vehicle that runs for months: a
// black box to replay when its heading is questioned. A series of recordings in one directory,
// DIR/headingd-YYYYmmddTHHMMSSZ.csv.zst (UTC at the file's first sample): a new file every
// `split_hours` of samples and at every start, so a restart never overwrites what was recorded;
// the series' files older than `keep_hours` are deleted as each new one starts, so the disk
// holds a bounded window. Each file is a whole recording (the sensor's provenance header, a
// closing line naming the next) that replays on its own.
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "pipeline/expendable_sink.hpp"
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
  // Beside DDS the series is expendable, and on a vehicle that runs for months a full disk is
  // seldom for ever (the series' own expiry, a log rotated, a file removed by hand): a file that
  // cannot be written is closed as far as it got, counted in `drops`, and the series resumes with
  // a new file after kRetryAfterS of samples (or one split, if shorter). Without this, a write
  // error throws OutputError as every file output's does.
  void resume_after_errors(OutputDrops& drops) { drops_ = &drops; }
  static constexpr double kRetryAfterS = 300.0;
  // Of samples since the series resumed, with some of them on the disk: no longer failing.
  static constexpr double kWritingAgainS = 10.0;
  // The file being written ("" before the first sample) and how many were started.
  std::string path() const { return current_ ? current_->path() : std::string(); }
  std::uint64_t files_started() const { return files_started_; }
  std::uint64_t files_deleted() const { return files_deleted_; }
  std::uint64_t files_lost() const { return files_lost_; }

 private:
  void start_file(double t_s);
  void delete_expired(double t_s);
  template <typename Call>
  void guarded(Call call, double t_s);
  void lose_file(const std::string& why, double t_s);
  std::string give_up_file();
  void count_loss(const std::string& why);

  RollingSettings settings_;
  std::string comments_;
  WallClock wall_;
  std::optional<RecordingSink> current_;
  double file_start_t_s_ = 0.0;
  std::string run_name_;  // the run's first file's name, without the ending: in every file's header
  // This run's files (name, first sample's time): their age is measured on the sample clock, which
  // a wall clock set at boot (NTP, no RTC) cannot step; their names' times can be years off.
  std::map<std::string, double> own_files_;
  std::uint64_t files_started_ = 0;
  std::uint64_t files_deleted_ = 0;
  OutputDrops* drops_ = nullptr;
  std::uint64_t files_lost_ = 0;
  bool counted_failing_ = false;        // in drops_->failing until a file works again
  std::optional<double> retry_at_t_s_;  // after a lost file: when the next one is tried
  double lost_at_t_s_ = 0.0;
  double resumed_at_t_s_ = 0.0;      // the first sample of the file that followed the loss
  bool wrote_since_resume_ = false;  // a file since then took samples without an error
};

// The time in a series file's name (UTC seconds), or nothing for any other name.
std::optional<double> rolling_file_time(const std::string& name);

}  // namespace headingd::pipeline
