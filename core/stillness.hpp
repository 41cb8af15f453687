#pragma once
// The paper's two stillness criteria (docs/algorithm.md, steps 2 and 3).
#include <array>
#include <cstddef>

#include "core/segment_stats.hpp"

namespace headingd::core {

// Criterion 2: rotation and vibration widen a segment's range; a still segment's range
// stays below k_range * sigma_still on every axis.
bool range_says_still(const SegmentStats& segment, const Vec3& sigma_still_dps, double k_range);

// Criterion 3: a still segment's mean lies within k_mean * sigma of the moving average of
// the last n accepted means. Fixed capacity, so accepting a segment never allocates.
class MeanHistory {
 public:
  static constexpr std::size_t kMaxMeans = 64;

  explicit MeanHistory(std::size_t n_means);

  void clear();
  void push(const Vec3& mean_dps);
  std::size_t size() const { return size_; }
  Vec3 moving_average_dps() const;  // zero when empty
  // True when empty: with no accepted history there is nothing to disagree with.
  bool consistent(const Vec3& mean_dps, const Vec3& sigma_dps, double k_mean) const;

 private:
  std::size_t capacity_;
  std::array<Vec3, kMaxMeans> means_{};
  std::size_t next_ = 0;
  std::size_t size_ = 0;
  Vec3 sum_ = Vec3::Zero();
};

}  // namespace headingd::core
