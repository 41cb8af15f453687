#pragma once
// Streaming statistics of one segment, per axis: O(1) per sample, no buffering.
// Welford's update keeps the variance accurate even when the mean (the bias) is
// large compared with the noise.
#include <cstdint>

#include "core/sample.hpp"

namespace headingd::core {

class SegmentStats {
 public:
  void reset();
  void add(const Vec3& rate_dps);

  std::uint32_t count() const { return count_; }
  const Vec3& mean_dps() const { return mean_; }
  // Per-sample standard deviation (n - 1 denominator); zero below two samples.
  Vec3 sigma_dps() const;
  const Vec3& min_dps() const { return min_; }
  const Vec3& max_dps() const { return max_; }
  Vec3 range_dps() const { return max_ - min_; }

 private:
  std::uint32_t count_ = 0;
  Vec3 mean_ = Vec3::Zero();
  Vec3 m2_ = Vec3::Zero();  // sum of squared deviations from the running mean
  Vec3 min_ = Vec3::Zero();
  Vec3 max_ = Vec3::Zero();
};

}  // namespace headingd::core
