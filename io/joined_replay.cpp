#include "io/joined_replay.hpp"

#include "io/native_csv.hpp"

namespace headingd::drivers {

JoinedReplaySource::JoinedReplaySource(std::vector<std::string> paths) : paths_(std::move(paths)) {
  if (paths_.empty()) throw OpenError("no recordings to join");
  current_ = std::make_unique<CsvReplaySource>(paths_.front());
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
      damaged_.push_back({paths_[index_], error.what()});
    } catch (const InputError& error) {
      damaged_.push_back({paths_[index_], error.what()});
    }
  }
}

std::size_t JoinedReplaySource::read(std::span<core::Sample> out) {
  while (current_) {
    std::size_t n = 0;
    try {
      n = current_->read(out);
    } catch (const InputError& error) {
      // A part cut short (a file lost to a full disk keeps what fit) or damaged: its good samples
      // were replayed; the rest of the series still is. The last part's error ends the replay as
      // any recording's does.
      if (index_ + 1 >= paths_.size()) throw;
      damaged_.push_back({paths_[index_], error.what()});
      after_run_end_ = false;
      current_.reset();
      current_started_ = false;
      open_next();
      continue;
    }
    if (n == 0) {
      open_next();
      continue;
    }
    if (!current_started_ && samples_ > 0 && !(out[0].t_s > last_t_s_))
      throw InputError(paths_[index_], 0,
                       "its first sample (t = " + std::to_string(out[0].t_s) + " s) is not after the last of " +
                           last_part_ + " (t = " + std::to_string(last_t_s_) +
                           " s): not the next part of one run (replay them apart, or in the order they were written)");
    if (!current_started_ && after_run_end_) boundaries_.push_back({paths_[index_], out[0].t_s - last_t_s_});
    if (!current_started_) last_part_ = paths_[index_];
    current_started_ = true;
    if (samples_ == 0) first_t_s_ = out[0].t_s;
    last_t_s_ = out[n - 1].t_s;
    samples_ += n;
    return n;
  }
  index_ = paths_.size();
  return 0;
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
