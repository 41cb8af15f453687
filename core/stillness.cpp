#include "core/stillness.hpp"

#include <algorithm>

namespace headingd::core {

bool range_says_still(const SegmentStats& segment, const Vec3& sigma_still_dps, double k_range) {
  if (segment.count() < 2) return false;
  return (segment.range_dps().array() < k_range * sigma_still_dps.array()).all();
}

MeanHistory::MeanHistory(std::size_t n_means) : capacity_(std::clamp<std::size_t>(n_means, 1, kMaxMeans)) {}

void MeanHistory::clear() {
  next_ = 0;
  size_ = 0;
  sum_.setZero();
}

void MeanHistory::push(const Vec3& mean_dps) {
  if (size_ == capacity_) {
    sum_ -= means_[next_];
  } else {
    ++size_;
  }
  means_[next_] = mean_dps;
  sum_ += mean_dps;
  next_ = (next_ + 1) % capacity_;
  // Re-sum now and then so rounding in the running sum cannot build up over months.
  if (next_ == 0) {
    sum_.setZero();
    for (std::size_t i = 0; i < size_; ++i) sum_ += means_[i];
  }
}

Vec3 MeanHistory::moving_average_dps() const {
  if (size_ == 0) return Vec3::Zero();
  return sum_ / static_cast<double>(size_);
}

bool MeanHistory::consistent(const Vec3& mean_dps, const Vec3& sigma_dps, double k_mean) const {
  if (size_ == 0) return true;
  return ((mean_dps - moving_average_dps()).array().abs() <= k_mean * sigma_dps.array()).all();
}

}  // namespace headingd::core
