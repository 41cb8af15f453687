#include "pipeline/rolling_recording_sink.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>

#include "io/csv_out.hpp"
#include "io/native_csv.hpp"
#include "service/log.hpp"

namespace headingd::pipeline {
namespace {

constexpr const char* kPrefix = "headingd-";
constexpr const char* kEnding = ".csv.zst";
constexpr std::size_t kStampChars = 16;  // YYYYmmddTHHMMSSZ

std::string stamp_of(double utc_s) {
  const std::time_t seconds = static_cast<std::time_t>(std::floor(utc_s));
  std::tm parts{};
  gmtime_r(&seconds, &parts);
  char text[32];
  std::strftime(text, sizeof text, "%Y%m%dT%H%M%SZ", &parts);
  return text;
}

bool exists(const std::string& path) {
  struct stat info {};
  return ::lstat(path.c_str(), &info) == 0;
}

}  // namespace

std::optional<double> rolling_file_time(const std::string& name) {
  const std::string prefix = kPrefix, ending = kEnding;
  if (name.size() < prefix.size() + kStampChars + ending.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - ending.size(), ending.size(), ending) != 0)
    return std::nullopt;
  const std::string stamp = name.substr(prefix.size(), kStampChars);
  // What may follow the stamp: nothing, or "_NNN" (files started within one second; '_' sorts after
  // the '.' of the first one's ending, and the count has three digits, so the names sort in the
  // order the files were started, which `replay --join DIR` relies on). Any count is read.
  const std::string rest =
      name.substr(prefix.size() + kStampChars, name.size() - prefix.size() - kStampChars - ending.size());
  if (!rest.empty() &&
      (rest[0] != '_' || rest.size() < 2 || rest.find_first_not_of("0123456789", 1) != std::string::npos))
    return std::nullopt;
  std::tm parts{};
  const char* end = strptime(stamp.c_str(), "%Y%m%dT%H%M%SZ", &parts);
  if (end == nullptr || *end != '\0') return std::nullopt;
  return static_cast<double>(timegm(&parts));
}

RollingRecordingSink::RollingRecordingSink(RollingSettings settings, std::string comments, WallClock wall)
    : settings_(std::move(settings)), comments_(std::move(comments)), wall_(wall) {
  std::error_code error;
  std::filesystem::create_directories(settings_.dir, error);
  if (error) throw app::OutputError("cannot create the recording directory " + settings_.dir + ": " + error.message());
}

void RollingRecordingSink::add(const core::Sample& sample, const core::Estimate& estimate,
                               const core::Estimator& estimator) {
  if (retry_at_t_s_) {
    if (sample.t_s < *retry_at_t_s_) return;  // the gap after a lost file
    guarded([&] { start_file(sample.t_s); }, sample.t_s);
    if (!current_) return;
    resumed_at_t_s_ = sample.t_s;
    wrote_since_resume_ = false;
    app::log(app::LogPriority::Notice, "rolling recording resumed",
             "recording again in " + current_->path() + " after " +
                 std::to_string(std::lround(sample.t_s - lost_at_t_s_)) + " s of samples not recorded");
  } else if (!current_ || sample.t_s - file_start_t_s_ >= settings_.split_hours * 3600.0) {
    guarded([&] { start_file(sample.t_s); }, sample.t_s);
    if (!current_) return;
  }
  guarded([&] { current_->add(sample, estimate, estimator); }, sample.t_s);
  // Writing again, not only open: a file takes a full disk's error only when its bytes go out
  // (RecordingSink hands them on once a wall-clock second, a split closes the file), so the series
  // counts as working once samples reached the disk and kWritingAgainS of them have passed since it
  // resumed, across splits, at any replay speed.
  if (current_ && current_->samples_on_disk()) wrote_since_resume_ = true;
  if (counted_failing_ && current_ && wrote_since_resume_ && sample.t_s - resumed_at_t_s_ >= kWritingAgainS) {
    --drops_->failing;
    counted_failing_ = false;
  }
}

// Without resume_after_errors, as any file output: the error ends the run (or the ExpendableSink
// around us drops the series). With it, the file is given up and a later one tried.
template <typename Call>
void RollingRecordingSink::guarded(Call call, double t_s) {
  if (drops_ == nullptr) return call();
  try {
    call();
    retry_at_t_s_.reset();
  } catch (const app::OutputClosed&) {
    throw;
  } catch (const app::OutputError& error) {
    lose_file(error.what(), t_s);
  }
}

// Closes the file as far as the disk took it (a second error on the way is the same loss, not
// reported twice); one that got nothing onto the disk is removed rather than left to clutter the
// series. Says what is left of it.
std::string RollingRecordingSink::give_up_file() {
  if (!current_) return "no file was open";
  const std::string path = current_->path();
  current_.reset();
  struct stat info {};
  if (::lstat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode) && info.st_size == 0) {
    ::unlink(path.c_str());
    return path + " held nothing and is removed";
  }
  return path + " keeps what was written";
}

void RollingRecordingSink::count_loss(const std::string& why) {
  ++files_lost_;
  ++drops_->count;
  if (!counted_failing_) ++drops_->failing, counted_failing_ = true;
  drops_->last = "rolling recording: " + why;
}

void RollingRecordingSink::lose_file(const std::string& why, double t_s) {
  const std::string left = give_up_file();
  if (!retry_at_t_s_) lost_at_t_s_ = t_s;
  const double wait_s = std::min(kRetryAfterS, settings_.split_hours * 3600.0);
  retry_at_t_s_ = t_s + wait_s;
  count_loss(why);
  app::log(app::LogPriority::Error, "output dropped rolling recording",
           "the rolling recording could not be written (" + why + "); " + left + "; a new file is tried after " +
               std::to_string(std::lround(wait_s)) + " s of samples; heading and status are still published");
}

void RollingRecordingSink::start_file(double t_s) {
  const std::string stamp = stamp_of(wall_());
  std::string path = settings_.dir + "/" + kPrefix + stamp + kEnding;
  for (int n = 1; exists(path); ++n) {  // never over an earlier file, not even one started this second
    char count[16];
    std::snprintf(count, sizeof count, "_%03d", n);
    path = settings_.dir + "/" + kPrefix + stamp + count + kEnding;
  }
  if (current_) {
    current_->close("# continued in " + std::filesystem::path(path).filename().string());
    current_.reset();
    wrote_since_resume_ = true;  // closed without an error: all of it is on the disk
  }
  // The folder again: removed by hand under a running daemon (a clean-up), it comes back rather than
  // costing every file until a restart.
  std::error_code missing;
  std::filesystem::create_directories(settings_.dir, missing);
  delete_expired(t_s);  // first: on a full disk, what expires makes the room for the next file
  std::string name = std::filesystem::path(path).filename().string();
  if (run_name_.empty()) run_name_ = name.substr(0, name.size() - std::strlen(kEnding));
  current_.emplace(path, comments_ + "# " + app::kSeriesRunComment + run_name_ + ", file " +
                             std::to_string(files_started_ + 1) + "\n");
  own_files_[name] = t_s;
  file_start_t_s_ = t_s;
  ++files_started_;
}

// Only names of the series (rolling_file_time), only regular files (a link is not followed nor
// removed); a directory we cannot list is said and left. Earlier runs' files are aged by the time
// in their names; this run's by the sample clock (`t_s`: the next file's first sample), so a wall
// clock stepped by years mid-run (set at boot on a computer without a battery-backed clock) does
// not delete the run's own recent files.
void RollingRecordingSink::delete_expired(double t_s) {
  DIR* dir = ::opendir(settings_.dir.c_str());
  if (dir == nullptr) {
    app::log(app::LogPriority::Warning, "recording expiry",
             "cannot list " + settings_.dir + " to delete old recordings: " + std::strerror(errno));
    return;
  }
  const double oldest_kept_s = wall_() - settings_.keep_hours * 3600.0;
  while (const dirent* entry = ::readdir(dir)) {
    const std::string name = entry->d_name;
    const auto started = rolling_file_time(name);
    const std::string path = settings_.dir + "/" + name;
    if (!started) continue;
    const auto own = own_files_.find(name);
    if (own != own_files_.end() ? t_s - own->second <= settings_.keep_hours * 3600.0 : *started >= oldest_kept_s)
      continue;
    struct stat info {};
    if (::fstatat(::dirfd(dir), name.c_str(), &info, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISREG(info.st_mode)) continue;
    if (::unlinkat(::dirfd(dir), name.c_str(), 0) == 0) {
      ++files_deleted_;
      if (own != own_files_.end()) own_files_.erase(own);
    } else
      app::log(app::LogPriority::Warning, "recording expiry", "cannot delete " + path + ": " + std::strerror(errno));
  }
  ::closedir(dir);
  // What is past the keep and gone by other hands (the folder cleaned) is not looked for again.
  std::erase_if(own_files_, [&](const auto& file) { return t_s - file.second > settings_.keep_hours * 3600.0; });
}

void RollingRecordingSink::finish(const core::Estimator& estimator, const core::SampleSource& source) {
  if (!current_) return;
  if (drops_ == nullptr) return current_->finish(estimator, source);
  try {
    current_->finish(estimator, source);
  } catch (const app::OutputClosed&) {
    throw;
  } catch (const app::OutputError& error) {
    count_loss(error.what());
    const std::string left = give_up_file();
    app::log(app::LogPriority::Error, "output dropped rolling recording",
             std::string("the last file of the rolling recording could not be closed (") + error.what() + "); " + left);
  }
}

}  // namespace headingd::pipeline
