#include "pipeline/read_ahead.hpp"

#include <algorithm>

namespace headingd::pipeline {

ReadAheadSource::ReadAheadSource(core::SampleSource& inner, Fraction fraction, std::size_t block_samples,
                                 std::size_t blocks)
    : inner_(inner), fraction_(std::move(fraction)), ring_(blocks) {
  for (Block& block : ring_.blocks()) block.samples.resize(std::max<std::size_t>(block_samples, 1));
  health_ = inner_.health();
}

ReadAheadSource::~ReadAheadSource() { close(); }

void ReadAheadSource::produce() {
  while (Block* block = ring_.next_empty()) {
    block->count = 0;
    block->end = false;
    block->error = nullptr;
    try {
      block->count = inner_.read(block->samples);
      block->end = block->count == 0;
    } catch (...) {
      block->error = std::current_exception();
    }
    block->health = inner_.health();
    block->counters = inner_.counters_text();
    if (fraction_) block->fraction = fraction_();
    const bool last = block->end || block->error;
    ring_.publish();
    if (last) return;
  }
}

bool ReadAheadSource::take_next_block() {
  if (ended_) return false;
  if (current_ != nullptr) {  // the finished block goes back to the reader
    current_ = nullptr;
    ring_.give_back();
  }
  if (!reader_.joinable()) reader_ = std::thread([this] { produce(); });
  current_ = &ring_.next_filled();
  offset_ = 0;
  health_ = current_->health;
  counters_ = current_->counters;
  fraction_read_ = current_->fraction;
  if (current_->error) {
    ended_ = true;
    std::rethrow_exception(current_->error);
  }
  if (current_->end) {
    ended_ = true;
    return false;
  }
  return true;
}

std::span<const core::Sample> ReadAheadSource::next(std::span<core::Sample> scratch) {
  if (scratch.empty() || closed_) return {};
  if ((current_ == nullptr || offset_ == current_->count) && !take_next_block()) return {};
  const std::size_t count = std::min(scratch.size(), current_->count - offset_);
  const std::span<const core::Sample> view(current_->samples.data() + offset_, count);
  offset_ += count;
  return view;
}

std::size_t ReadAheadSource::read(std::span<core::Sample> out) {
  const std::span<const core::Sample> view = next(out);
  std::copy(view.begin(), view.end(), out.begin());
  return view.size();
}

void ReadAheadSource::close() {
  if (closed_) return;
  closed_ = true;
  ring_.close();
  if (reader_.joinable()) reader_.join();
  inner_.close();
}

}  // namespace headingd::pipeline
