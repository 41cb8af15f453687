#include "core/segment_stats.hpp"

namespace headingd::core {

void SegmentStats::reset() { *this = SegmentStats{}; }

void SegmentStats::add(const Vec3& rate_dps) {
  ++count_;
  if (count_ == 1) {
    mean_ = rate_dps;
    m2_.setZero();
    min_ = rate_dps;
    max_ = rate_dps;
    return;
  }
  const Vec3 delta = rate_dps - mean_;
  mean_ += delta / static_cast<double>(count_);
  m2_ += delta.cwiseProduct(rate_dps - mean_);
  min_ = min_.cwiseMin(rate_dps);
  max_ = max_.cwiseMax(rate_dps);
}

Vec3 SegmentStats::sigma_dps() const {
  if (count_ < 2) return Vec3::Zero();
  return (m2_ / static_cast<double>(count_ - 1)).cwiseSqrt();
}

}  // namespace headingd::core
