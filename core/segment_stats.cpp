#include "core/segment_stats.hpp"

namespace headingd::core {

void SegmentStats::reset() { *this = SegmentStats{}; }

Vec3 SegmentStats::mean_dps() const {
  if (count_ == 0) return Vec3::Zero();
  return shift_ + sum_ / static_cast<double>(count_);
}

Vec3 SegmentStats::sigma_dps() const {
  if (count_ < 2) return Vec3::Zero();
  const double n = count_;
  const Vec3 squares = (sum_sq_ - sum_.cwiseAbs2() / n).cwiseMax(0.0);  // about the mean
  return (squares / (n - 1.0)).cwiseSqrt();
}

}  // namespace headingd::core
