#pragma once
// A bounded ring of blocks between one producer thread and one consumer thread: the producer
// fills the next empty block and publishes it, the consumer takes the next filled block and
// gives it back when done. Hand-over by two counters and C++20 atomic waits (futexes); the
// blocks are large (thousands of samples, a megabyte of text), so this costs nothing per item.
// The producer waits while the ring is full; close() wakes it for good.
#include <atomic>
#include <cstdint>
#include <vector>

namespace headingd::drivers {

template <typename Block>
class SpscRing {
 public:
  explicit SpscRing(std::size_t blocks) : blocks_(blocks < 2 ? 2 : blocks) {}
  SpscRing(const SpscRing&) = delete;
  SpscRing& operator=(const SpscRing&) = delete;

  std::vector<Block>& blocks() { return blocks_; }  // to size them before the producer starts

  // Producer: the next block to fill, waiting for room; nullptr once closed.
  Block* next_empty() {
    while (true) {
      const std::uint64_t given_back = consumed_.load(std::memory_order_acquire);
      if (closed_.load(std::memory_order_acquire)) return nullptr;
      if (produced_.load(std::memory_order_relaxed) - given_back < blocks_.size())
        return &blocks_[produced_.load(std::memory_order_relaxed) % blocks_.size()];
      consumed_.wait(given_back, std::memory_order_acquire);
    }
  }
  // Producer: the block from next_empty() is ready for the consumer.
  void publish() {
    produced_.fetch_add(1, std::memory_order_release);
    produced_.notify_one();
  }

  // Consumer: the next filled block, waiting for it.
  Block& next_filled() {
    const std::uint64_t wanted = consumed_.load(std::memory_order_relaxed);
    for (std::uint64_t filled = produced_.load(std::memory_order_acquire); filled <= wanted;
         filled = produced_.load(std::memory_order_acquire)) {
      produced_.wait(filled, std::memory_order_acquire);
    }
    return blocks_[wanted % blocks_.size()];
  }
  // Consumer: the block from next_filled() may be filled again.
  void give_back() {
    consumed_.fetch_add(1, std::memory_order_release);
    consumed_.notify_one();
  }

  // Either side: no more blocks will be taken; a producer waiting for room returns nullptr.
  void close() {
    closed_.store(true, std::memory_order_release);
    consumed_.fetch_add(1, std::memory_order_release);  // a change, so that a waiting producer wakes
    consumed_.notify_one();
  }

 private:
  std::vector<Block> blocks_;
  std::atomic<std::uint64_t> produced_{0};  // blocks published, from the start
  std::atomic<std::uint64_t> consumed_{0};  // blocks given back (plus one after close)
  std::atomic<bool> closed_{false};
};

}  // namespace headingd::drivers
