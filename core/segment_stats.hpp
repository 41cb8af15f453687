#pragma once
// Streaming statistics of one segment, per axis: O(1) per sample, no buffering.
// Sums of the samples less the segment's first sample: the shift takes out the mean (the
// bias), which may be large against the noise, so the variance is as accurate as Welford's
// update gives, without its division on every sample.
#include <cstddef>
#include <cstdint>

#include "core/sample.hpp"

namespace headingd::core {

class SegmentStats {
 public:
  void reset();
  void add(const Vec3& rate_dps) {
    if (count_++ == 0) {
      shift_ = rate_dps;
      min_ = rate_dps;
      max_ = rate_dps;
      return;
    }
    const Vec3 d = rate_dps - shift_;
    sum_ += d;
    sum_sq_ += d.cwiseAbs2();
    min_ = min_.cwiseMin(rate_dps);
    max_ = max_.cwiseMax(rate_dps);
  }

  // add() on each of `count` samples, the sums held in registers (a replay's fast path). The
  // segment must have its first sample already.
  void add_run(const Sample* samples, std::size_t count) {
    Vec3 sum = sum_, sum_sq = sum_sq_, low = min_, high = max_;
    for (std::size_t i = 0; i < count; ++i) {
      const Vec3& rate_dps = samples[i].rate_dps;
      const Vec3 d = rate_dps - shift_;
      sum += d;
      sum_sq += d.cwiseAbs2();
      low = low.cwiseMin(rate_dps);
      high = high.cwiseMax(rate_dps);
    }
    sum_ = sum, sum_sq_ = sum_sq, min_ = low, max_ = high;
    count_ += static_cast<std::uint32_t>(count);
  }

  std::uint32_t count() const { return count_; }
  Vec3 mean_dps() const;
  // Per-sample standard deviation (n - 1 denominator); zero below two samples.
  Vec3 sigma_dps() const;
  const Vec3& min_dps() const { return min_; }
  const Vec3& max_dps() const { return max_; }
  Vec3 range_dps() const { return max_ - min_; }

 private:
  std::uint32_t count_ = 0;
  Vec3 shift_ = Vec3::Zero();   // the first sample
  Vec3 sum_ = Vec3::Zero();     // of (sample - shift)
  Vec3 sum_sq_ = Vec3::Zero();  // of (sample - shift)^2
  Vec3 min_ = Vec3::Zero();
  Vec3 max_ = Vec3::Zero();
};

}  // namespace headingd::core
