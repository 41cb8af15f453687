#include "hw/sample_clock.hpp"

#include <algorithm>
#include <cmath>

namespace headingd::drivers {
namespace {
constexpr std::uint64_t kMinBaselineSamples = 64;         // before this, keep the nominal period
constexpr std::int64_t kRebaseAfterNs = 120'000'000'000;  // track slow drift of the chip's oscillator
}  // namespace

SampleClock::SampleClock(double nominal_hz) : nominal_period_ns_(1e9 / nominal_hz), period_ns_(1e9 / nominal_hz) {}

void SampleClock::restart() {
  has_base_ = has_last_ = has_mid_ = false;
  period_ns_ = period_ns_ > 0 ? period_ns_ : nominal_period_ns_;
}

void SampleClock::anchor(std::uint64_t index, std::int64_t t_ns, bool provisional) {
  if (has_last_ && index <= last_index_) return;
  if (provisional) {
    last_index_ = index;
    last_ns_ = t_ns;
    has_last_ = true;
    return;
  }
  if (!has_base_) {
    base_index_ = index;
    base_ns_ = t_ns;
    has_base_ = true;
  } else if (index - base_index_ >= kMinBaselineSamples) {
    const double estimate = static_cast<double>(t_ns - base_ns_) / static_cast<double>(index - base_index_);
    // An absurd estimate (a clock step, a counting error) is ignored rather than trusted.
    if (estimate > 0.5 * nominal_period_ns_ && estimate < 2.0 * nominal_period_ns_) period_ns_ = estimate;
  }
  if (!has_mid_ && t_ns - base_ns_ > kRebaseAfterNs / 2) {
    mid_index_ = index;
    mid_ns_ = t_ns;
    has_mid_ = true;
  }
  if (has_mid_ && t_ns - base_ns_ > kRebaseAfterNs) {
    base_index_ = mid_index_;
    base_ns_ = mid_ns_;
    has_mid_ = false;
  }
  last_index_ = index;
  last_ns_ = t_ns;
  has_last_ = true;
}

std::int64_t SampleClock::stamp(std::uint64_t index) {
  const double offset = static_cast<double>(static_cast<std::int64_t>(index) - static_cast<std::int64_t>(last_index_));
  std::int64_t t = last_ns_ + std::llround(offset * period_ns_);
  if (stamped_ && t <= previous_stamp_ns_)
    t = previous_stamp_ns_ + std::max<std::int64_t>(1, std::llround(period_ns_ / 2));
  previous_stamp_ns_ = t;
  stamped_ = true;
  return t;
}

}  // namespace headingd::drivers
