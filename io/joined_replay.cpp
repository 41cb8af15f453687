#include "io/joined_replay.hpp"

#include <algorithm>
#include <charconv>

#include "io/native_csv.hpp"

namespace headingd::drivers {
namespace {

std::optional<SeriesPosition> position_in(const CsvReplaySource& file) {
  const std::string_view key = app::kSeriesRunComment, number = ", file ";
  for (const auto& comment : file.comments()) {
    const auto comma = comment.find(number);
    if (!comment.starts_with(key) || comma == std::string::npos) continue;
    long n = 0;
    const char* digits = comment.data() + comma + number.size();
    const auto [end, error] = std::from_chars(digits, comment.data() + comment.size(), n);
    if (error != std::errc() || end != comment.data() + comment.size() || n < 1) continue;
    return SeriesPosition{comment.substr(key.size(), comma - key.size()), n};
  }
  return std::nullopt;
}

// The run a rolling series' file names in its header, "" if it names none.
std::string series_run_of(const CsvReplaySource& file) {
  const auto position = position_in(file);
  return position ? position->run : std::string();
}

}  // namespace

std::optional<SeriesPosition> series_position(const std::string& path) {
  try {
    const CsvReplaySource file(path);
    return position_in(file);
  } catch (const OpenError&) {
    return std::nullopt;
  } catch (const InputError&) {
    return std::nullopt;
  }
}

JoinedReplaySource::JoinedReplaySource(std::vector<std::string> paths, bool split_runs)
    : paths_(std::move(paths)), split_runs_(split_runs) {
  if (paths_.empty()) throw OpenError("no recordings to join");
  current_ = std::make_unique<CsvReplaySource>(paths_.front());
  current_run_ = series_run_of(*current_);
  description_ = std::to_string(paths_.size()) + " recordings joined, " + current_->describe() + " to " + paths_.back();
}

// The next file that opens; one that cannot (missing, a damaged header) is a damaged part.
void JoinedReplaySource::open_next() {
  if (current_) after_run_end_ = current_->last_comment().starts_with(app::kEndOfRunComment);
  current_.reset();
  current_started_ = false;
  while (!current_ && ++index_ < paths_.size()) {
    try {
      current_ = std::make_unique<CsvReplaySource>(paths_[index_]);
    } catch (const OpenError& error) {
      note_damage(error.what());
    } catch (const InputError& error) {
      note_damage(error.what());
    }
  }
  if (!current_) return;
  current_run_ = series_run_of(*current_);
  runs_named_ = !current_run_.empty() && !run_.empty();
  if (runs_named_) after_run_end_ = current_run_ != run_;
}

void JoinedReplaySource::note_damage(const std::string& error) {
  damaged_.push_back({paths_[index_], error});
  after_damage_ = true;
  after_run_end_ = false;
}

void JoinedReplaySource::take(std::span<const core::Sample> samples) {
  if (!current_started_) {
    last_part_ = paths_[index_];
    run_ = current_run_;
  }
  current_started_ = true;
  after_damage_ = false;
  if (samples_ == 0) first_t_s_ = samples.front().t_s;
  last_t_s_ = samples.back().t_s;
  samples_ += samples.size();
}

std::size_t JoinedReplaySource::read(std::span<core::Sample> out) {
  if (run_ended_) return 0;
  if (!held_.empty()) {  // this run's first samples, read while ending the run before
    const std::size_t n = std::min(out.size(), held_.size());
    std::copy_n(held_.begin(), n, out.begin());
    held_.erase(held_.begin(), held_.begin() + static_cast<std::ptrdiff_t>(n));
    take(out.first(n));
    return n;
  }
  while (current_) {
    if (split_runs_ && !current_started_ && after_run_end_ && samples_ > 0) {
      after_run_end_ = false;
      run_ended_ = true;  // the file before closed its run: the next one starts another
      return 0;
    }
    std::size_t n = 0;
    try {
      n = current_->read(out);
    } catch (const InputError& error) {
      // A part cut short (a file lost to a full disk, a run that crashed) or damaged: its good
      // samples were replayed; the rest of the series still is. The last part's error ends the
      // replay as any recording's does.
      if (index_ + 1 >= paths_.size()) throw;
      note_damage(error.what());
      current_.reset();
      open_next();
      continue;
    }
    if (n == 0) {
      open_next();
      continue;
    }
    if (!current_started_ && samples_ > 0 && !(out[0].t_s > last_t_s_)) {
      // After a run's end, or a part cut short (a crash), a clock that starts again is the
      // machine restarting: another run. Anywhere else the files are out of order.
      const bool new_boot = after_run_end_ || (after_damage_ && !runs_named_);
      if (split_runs_ && new_boot) {
        held_.assign(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n));
        run_ended_ = true;
        return 0;
      }
      throw InputError(paths_[index_], 0,
                       "its first sample (t = " + std::to_string(out[0].t_s) + " s) is not after the last of " +
                           last_part_ + " (t = " + std::to_string(last_t_s_) + " s): " +
                           (new_boot ? "another run, after the machine restarted (its sample clock starts again); "
                                       "--join with --output-dir replays each run as a row of its own"
                                     : "not the next part of one run (replay them apart, or in the order they were "
                                       "written)"));
    }
    if (!current_started_ && after_run_end_) boundaries_.push_back({paths_[index_], out[0].t_s - last_t_s_});
    take(out.first(n));
    return n;
  }
  index_ = paths_.size();
  return 0;
}

bool JoinedReplaySource::next_run() {
  if (!run_ended_) return false;
  run_ended_ = false;
  samples_ = 0;
  first_t_s_ = last_t_s_ = 0.0;
  boundaries_.clear();
  damaged_.clear();
  return true;
}

void JoinedReplaySource::close() {
  if (current_) current_->close();
  current_.reset();
  index_ = paths_.size();
}

core::SourceHealth JoinedReplaySource::health() const { return recording_health(samples_, first_t_s_, last_t_s_); }

std::optional<double> JoinedReplaySource::fraction_read() const {
  if (!current_) return index_ >= paths_.size() ? std::optional<double>(1.0) : std::nullopt;
  const auto within = current_->fraction_read();
  if (!within) return std::nullopt;
  return (static_cast<double>(index_) + *within) / static_cast<double>(paths_.size());
}

}  // namespace headingd::drivers
