#include "pipeline/read_ahead.hpp"

#include <algorithm>

namespace headingd::pipeline {

ReadAheadSource::ReadAheadSource(core::SampleSource& inner, Fraction fraction, std::size_t block_samples,
                                 std::size_t blocks)
    : inner_(inner), fraction_(std::move(fraction)), ring_(std::max<std::size_t>(blocks, 2)) {
  for (Block& block : ring_) block.samples.resize(std::max<std::size_t>(block_samples, 1));
  health_ = inner_.health();
}

ReadAheadSource::~ReadAheadSource() { close(); }

void ReadAheadSource::produce() {
  const std::uint64_t room = ring_.size();
  for (std::uint64_t n = 0;; ++n) {
    while (true) {  // wait for room
      const std::uint64_t given_back = consumed_.load(std::memory_order_acquire);
      if (closing_.load(std::memory_order_acquire)) return;
      if (n - given_back < room) break;
      consumed_.wait(given_back, std::memory_order_acquire);
    }
    Block& block = ring_[n % room];
    block.count = 0;
    block.end = false;
    block.error = nullptr;
    try {
      block.count = inner_.read(block.samples);
      block.end = block.count == 0;
    } catch (...) {
      block.error = std::current_exception();
    }
    block.health = inner_.health();
    block.counters = inner_.counters_text();
    if (fraction_) block.fraction = fraction_();
    produced_.store(n + 1, std::memory_order_release);
    produced_.notify_one();
    if (block.end || block.error) return;
  }
}

bool ReadAheadSource::take_next_block() {
  if (ended_) return false;
  std::uint64_t next = consumed_.load(std::memory_order_relaxed);
  if (current_ != nullptr) {  // give the finished block back to the reader
    current_ = nullptr;
    consumed_.store(++next, std::memory_order_release);
    consumed_.notify_one();
  }
  if (!reader_.joinable()) reader_ = std::thread([this] { produce(); });
  for (std::uint64_t filled = produced_.load(std::memory_order_acquire); filled <= next;
       filled = produced_.load(std::memory_order_acquire)) {
    produced_.wait(filled, std::memory_order_acquire);
  }
  current_ = &ring_[next % ring_.size()];
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

std::size_t ReadAheadSource::read(std::span<core::Sample> out) {
  if (out.empty() || closing_.load(std::memory_order_relaxed)) return 0;
  if ((current_ == nullptr || offset_ == current_->count) && !take_next_block()) return 0;
  const std::size_t count = std::min(out.size(), current_->count - offset_);
  std::copy_n(current_->samples.begin() + static_cast<std::ptrdiff_t>(offset_), count, out.begin());
  offset_ += count;
  return count;
}

void ReadAheadSource::close() {
  if (closing_.exchange(true)) return;
  consumed_.fetch_add(1, std::memory_order_release);  // wakes a reader waiting for room: it sees closing_
  consumed_.notify_one();
  if (reader_.joinable()) reader_.join();
  inner_.close();
}

}  // namespace headingd::pipeline
